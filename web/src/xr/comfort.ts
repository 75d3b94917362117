// Comfort in the headset, as pure functions: where the HUD panel goes so that it never
// covers the work area, and how strongly to narrow the view while the base moves (a tunnel
// vignette: seeing the world slide in the periphery is what makes people sick).

import type { Pose } from "../protocol";

export type HudMode = "wrist" | "hidden";
export type Vec3 = readonly [number, number, number];

/** Where the panel parks when the wrist is not raised: left of and a little below the eyes,
 * 50° off the robot's forward view, away from the hands' work in front. Rig frame (y up,
 * -z forward), relative to the headset. */
export const PARKED_OFFSET: Vec3 = [-0.55, -0.15, -0.45];
/** The panel sits this far above a raised left controller (a watch face), metres. */
export const WRIST_LIFT = 0.1;
/** The controller's top must point at least this much (cosine) towards the eyes. */
export const WRIST_FACING = 0.6;

export interface HudPlacement {
  visible: boolean;
  where: "wrist" | "parked" | "hidden";
  position: Vec3;
}

/** The controller's local +y axis (its top) in the rig frame, from its (x, y, z, qw, qx, qy, qz) pose. */
export function controllerUp(pose: Pose): Vec3 {
  const [, , , w, x, y, z] = pose;
  return [2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)];
}

function unit(v: Vec3): Vec3 {
  const n = Math.hypot(v[0], v[1], v[2]);
  return n < 1e-9 ? [0, 0, 0] : [v[0] / n, v[1] / n, v[2] / n];
}

/**
 * Where the HUD goes this frame. Looking at a raised left controller whose top faces the
 * eyes (a watch gesture) shows it on the wrist; otherwise it is parked off to the side.
 * Hands at work (palms turned in, reaching forward) never raise it over the work area.
 */
export function hudPlacement(mode: HudMode, left: Pose | null, headset: Vec3): HudPlacement {
  if (mode === "hidden") return { visible: false, where: "hidden", position: headset };
  if (left !== null) {
    const toEyes = unit([headset[0] - left[0], headset[1] - left[1], headset[2] - left[2]]);
    const up = controllerUp(left);
    const facing = up[0] * toEyes[0] + up[1] * toEyes[1] + up[2] * toEyes[2];
    const raised = left[1] > headset[1] - 0.55; // above chest height
    if (facing >= WRIST_FACING && raised) {
      return { visible: true, where: "wrist", position: [left[0], left[1] + WRIST_LIFT, left[2]] };
    }
  }
  const [dx, dy, dz] = PARKED_OFFSET;
  return { visible: true, where: "parked", position: [headset[0] + dx, headset[1] + dy, headset[2] + dz] };
}

/** Degrees between looking straight ahead (-z) from `eyes` and looking at `target`. */
export function offAxisDegrees(eyes: Vec3, target: Vec3): number {
  const d = unit([target[0] - eyes[0], target[1] - eyes[1], target[2] - eyes[2]]);
  return (Math.acos(Math.max(-1, Math.min(1, -d[2]))) * 180) / Math.PI;
}

/** Vignette strength 0..`max` for a base moving at `speed` m/s and turning at `yawRate`
 * rad/s: nothing below a crawl, full at 60 % of the robot's limits. */
export function vignetteStrength(
  speed: number,
  yawRate: number,
  limits: { linear: number; yaw: number },
  max = 0.75,
): number {
  const crawl = 0.05;
  const linear = Math.max(0, Math.abs(speed) - crawl) / (0.6 * limits.linear - crawl);
  const turning = Math.max(0, Math.abs(yawRate) - crawl) / (0.6 * limits.yaw - crawl);
  const s = Math.min(1, Math.max(linear, turning));
  return Number.isFinite(s) ? s * max : 0;
}

/** The base's speed and turn rate from successive simulation states (smoothed). */
export class BaseMotionMeter {
  speed = 0;
  yawRate = 0;
  private last: { t: number; x: number; y: number; yaw: number } | null = null;

  update(tSim: number, x: number, y: number, yaw: number): void {
    const last = this.last;
    this.last = { t: tSim, x, y, yaw };
    if (last === null) return;
    const dt = tSim - last.t;
    if (!(dt > 0) || dt > 1) {
      this.speed = 0; // a new trial, or a long pause: start over
      this.yawRate = 0;
      return;
    }
    const turn = Math.atan2(Math.sin(yaw - last.yaw), Math.cos(yaw - last.yaw));
    const k = Math.min(1, dt / 0.15);
    this.speed += k * (Math.hypot(x - last.x, y - last.y) / dt - this.speed);
    this.yawRate += k * (turn / dt - this.yawRate);
  }
}
