// Snap turns, a comfort option for the headset: instead of turning the base as long as the
// right thumbstick is held (the world then rotates around the operator, which makes many
// people sick), a flick of the stick asks the server for one snap (`snap_left` /
// `snap_right`: the base turns 30 degrees, timed on the sim clock there) and the view is
// blacked out until the drawn base has turned and stands still again.

/** The stick counts as flicked beyond this deflection, and as released again below the next. */
export const FLICK_ON = 0.7;
export const FLICK_OFF = 0.3;
/** The drawn base counts as turning above this yaw rate (rad/s)... */
export const TURNING_YAW_RATE = 0.2;
/** ...and as still again below this one. */
export const STILL_YAW_RATE = 0.05;
/** The view clears this long after a flick at the latest (s), whatever was drawn. */
export const MAX_BLACKOUT_S = 2.5;

export type TurnMode = "smooth" | "snap";
export type SnapDirection = "snap_left" | "snap_right";

export interface SnapOutput {
  /** A snap to ask the server for this frame. */
  ask: SnapDirection | null;
  /** Black the view out (a snap under way). */
  blackout: boolean;
}

export class SnapTurn {
  /** Snaps asked for so far. */
  snaps = 0;
  private armed = true;
  private since: number | null = null;
  private seenTurning = false;

  /** One frame at `now` (s): the raw right stick x (right positive) and the drawn base's
   * yaw rate (rad/s). */
  update(stickX: number, now: number, yawRate: number): SnapOutput {
    if (Math.abs(stickX) < FLICK_OFF) this.armed = true;
    if (this.since !== null) {
      if (Math.abs(yawRate) > TURNING_YAW_RATE) this.seenTurning = true;
      const over = (this.seenTurning && Math.abs(yawRate) < STILL_YAW_RATE) || now - this.since > MAX_BLACKOUT_S;
      if (!over) return { ask: null, blackout: true };
      this.since = null;
    }
    if (this.armed && Math.abs(stickX) >= FLICK_ON) {
      this.armed = false;
      this.since = now;
      this.seenTurning = false;
      this.snaps += 1;
      return { ask: stickX > 0 ? "snap_right" : "snap_left", blackout: true };
    }
    return { ask: null, blackout: false };
  }

  /** Whether a snap is under way (the view blacked out). */
  get active(): boolean {
    return this.since !== null;
  }
}
