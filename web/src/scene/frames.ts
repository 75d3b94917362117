// Coordinate frames. The server speaks the MuJoCo world frame (z up) and poses as
// (x, y, z, qw, qx, qy, qz); WebXR's local-floor frame is y up with -z forward. The world
// is drawn under one root group rotated from z-up to three.js's y-up, so every body pose
// from the server is applied verbatim inside it; this file is the only place that converts.

import * as THREE from "three";
import type { Pose } from "../protocol";

/** World (z up) → three.js (y up): a rotation of -90° about x, applied once at the root. */
export const WORLD_TO_THREE = new THREE.Quaternion().setFromAxisAngle(
  new THREE.Vector3(1, 0, 0),
  -Math.PI / 2,
);

/** Apply a protocol pose (x, y, z, qw, qx, qy, qz) to an object's local transform. */
export function applyPose(object: THREE.Object3D, pose: Pose): void {
  object.position.set(pose[0], pose[1], pose[2]);
  object.quaternion.set(pose[4], pose[5], pose[6], pose[3]);
}

/** A world-frame point (z up) in three.js scene coordinates (y up). */
export function worldToThree(x: number, y: number, z: number): THREE.Vector3 {
  return new THREE.Vector3(x, z, -y);
}

/** The heading (rotation about world z) of a pose's orientation. */
export function yawOf(pose: Pose): number {
  const [, , , w, x, y, z] = pose;
  return Math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
}

/** A WebXR rigid transform as a protocol pose (x, y, z, qw, qx, qy, qz). */
export function xrPose(transform: XRRigidTransform): Pose {
  const p = transform.position;
  const q = transform.orientation;
  return [p.x, p.y, p.z, q.w, q.x, q.y, q.z];
}

/** Round a pose for the wire (0.1 mm, 1e-5 in the quaternion): smaller and deterministic. */
export function roundPose(pose: Pose): Pose {
  const r = (v: number, k: number): number => Math.round(v * k) / k;
  return [
    r(pose[0], 1e4),
    r(pose[1], 1e4),
    r(pose[2], 1e4),
    r(pose[3], 1e5),
    r(pose[4], 1e5),
    r(pose[5], 1e5),
    r(pose[6], 1e5),
  ];
}

/**
 * The rig rotation (about three.js y) that makes the rig's forward (-z, as WebXR's
 * local-floor) point along a robot heading `yaw` (world frame, counter-clockwise from +x).
 */
export function rigYawForHeading(yaw: number): number {
  return yaw - Math.PI / 2;
}
