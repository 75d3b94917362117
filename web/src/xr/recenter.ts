// Recentering the headset view: whichever way the operator faces when they ask for it
// becomes the robot's forward. Every XR pose (headset, controllers) is turned about the
// vertical axis through the headset by -yaw before it is used or sent, so the server sees
// the operator facing forward; the rig is turned the other way so the drawn world agrees.

import type { Pose } from "../protocol";

export interface Recenter {
  /** The headset's heading when recentered (radians about +y, 0 = facing -z). */
  yaw: number;
  /** The vertical axis it turns about: the headset's x and z then (local-floor, metres). */
  x: number;
  z: number;
}

export const NO_RECENTER: Recenter = { yaw: 0, x: 0, z: 0 };

/** The heading about +y of a local-floor pose's orientation (0 when looking down -z). */
export function headingOf(pose: Pose): number {
  const [, , , w, x, y, z] = pose;
  // forward = orientation applied to (0, 0, -1)
  const fx = -2 * (x * z + w * y);
  const fz = -(1 - 2 * (x * x + y * y));
  return Math.atan2(-fx, -fz);
}

/** The recentering that makes `headset`'s current heading forward. */
export function recenterOn(headset: Pose): Recenter {
  return { yaw: headingOf(headset), x: headset[0], z: headset[2] };
}

/** `pose` in the recentered frame: turned by -yaw about the vertical axis through (x, z). */
export function applyRecenter(pose: Pose, r: Recenter): Pose {
  if (r.yaw === 0) return pose;
  const c = Math.cos(-r.yaw);
  const s = Math.sin(-r.yaw);
  const dx = pose[0] - r.x;
  const dz = pose[2] - r.z;
  // rotation about +y by angle a: x' = x cos a + z sin a, z' = -x sin a + z cos a
  const px = r.x + dx * c + dz * s;
  const pz = r.z - dx * s + dz * c;
  // q' = q_y(-yaw) * q, q_y(a) = (w = cos a/2, y = sin a/2)
  const hw = Math.cos(-r.yaw / 2);
  const hy = Math.sin(-r.yaw / 2);
  const [, , , w, x, y, z] = pose;
  return [
    px,
    pose[1],
    pz,
    hw * w - hy * y,
    hw * x + hy * z,
    hw * y + hy * w,
    hw * z - hy * x,
  ];
}

/** The recentering undone: maps recentered poses back to raw local-floor. */
export function undo(r: Recenter): Recenter {
  return { yaw: -r.yaw, x: r.x, z: r.z };
}

/** A point through `applyRecenter` (or, with `undo(r)`, back). */
export function recenterPoint(p: readonly [number, number, number], r: Recenter): [number, number, number] {
  const [x, y, z] = applyRecenter([p[0], p[1], p[2], 1, 0, 0, 0], r);
  return [x, y, z];
}
