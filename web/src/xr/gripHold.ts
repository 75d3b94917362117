// The headset's take-over gesture: both grips squeezed past a threshold and held for a
// moment while an autonomous driver (expert, policy) drives. It fires once per hold, so
// grips kept squeezed after the take-over (the person now drives with them) do nothing.

import type { Hud } from "../protocol";

/** How far a grip must be squeezed (0..1) to count. */
export const GRIP_HOLD_THRESHOLD = 0.8;
/** How long both grips must stay squeezed (s). */
export const GRIP_HOLD_S = 0.6;

export class GripHold {
  private since: number | null = null;
  private fired = false;

  /** One frame: both grip values and the time (s); `armed`: a take-over is possible now.
   * True on the frame the hold completes. */
  update(left: number, right: number, t: number, armed: boolean): boolean {
    const held = left >= GRIP_HOLD_THRESHOLD && right >= GRIP_HOLD_THRESHOLD;
    if (!held) {
      this.since = null;
      this.fired = false;
      return false;
    }
    if (this.since === null) this.since = t;
    if (!armed || this.fired || t - this.since < GRIP_HOLD_S) return false;
    this.fired = true;
    return true;
  }
}

/** The in-VR menu's label of its take-over item, for the HUD the session sent. */
export function drivingLabel(hud: Hud | null): string {
  if (hud === null || hud.driver === "person") return "You drive";
  return hud.taken_over ? `Hand back to ${hud.driver}` : `Take over from ${hud.driver}`;
}
