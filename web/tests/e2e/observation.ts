// What the scripted operator sees: the page's snapshot and body poses turned into an
// observation in the world and robot base frames (metres, radians; world z up, base frame
// x forward, y left, z up), and the small vector geometry it works with.

import type { Pose } from "../../src/protocol";
import type { DebugSnapshot } from "./lib.js";

export type Vec3 = [number, number, number];
/** A base pose in the world: x, y, yaw. */
export type Base = Vec3;

export interface BoxSeen {
  name: string;
  pos: Vec3;
  yaw: number;
}

/** What an operator can see. */
export interface Observation {
  t: number;
  phase: string | null;
  base: Base;
  boxes: BoxSeen[];
  tcp: [Vec3, Vec3];
  targets: [Vec3 | null, Vec3 | null];
  following: readonly [boolean, boolean];
  holding: boolean;
  zone: [number, number];
}

/** Desired TCP positions of both hands in the robot base frame. */

export const wrap = (a: number): number => Math.atan2(Math.sin(a), Math.cos(a));

export function yawOf(pose: Pose): number {
  const [, , , w, x, y, z] = pose;
  return Math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
}

export function toBase(base: Base, p: Vec3): Vec3 {
  const [bx, by, yaw] = base;
  const dx = p[0] - bx;
  const dy = p[1] - by;
  const c = Math.cos(yaw);
  const s = Math.sin(yaw);
  return [c * dx + s * dy, -s * dx + c * dy, p[2]];
}

export const sub = (a: Vec3, b: Vec3): Vec3 => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
export const add = (a: Vec3, b: Vec3): Vec3 => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
export const norm = (a: readonly number[]): number => Math.hypot(...a);
const position = (pose: Pose): Vec3 => [pose[0], pose[1], pose[2]];

/** Observation from a page snapshot and the bodies' poses (which hold a `base`). */
export function observe(snap: DebugSnapshot, bodies: Record<string, Pose> & { base: Pose }): Observation {
  const basePose = bodies.base;
  const base: Base = [basePose[0], basePose[1], yawOf(basePose)];
  const boxes = Object.entries(bodies)
    .filter(([name]) => /^box_\d+$/.test(name))
    .map(([name, pose]) => ({ name, pos: position(pose), yaw: yawOf(pose) }));
  const hand = (name: string): Pose => {
    const pose = bodies[name];
    if (pose === undefined) throw new Error(`no body ${name} in the scene`);
    return pose;
  };
  const tcp: [Vec3, Vec3] = [tcpOf(hand("hand_l")), tcpOf(hand("hand_r"))];
  const sent = snap.state?.tcp_targets;
  const targets: [Vec3 | null, Vec3 | null] = sent ? [position(sent[0]), position(sent[1])] : [null, null];
  return {
    t: snap.state?.t_sim ?? 0,
    phase: snap.hud?.phase ?? null,
    base,
    boxes,
    tcp,
    targets,
    following: snap.state?.following ?? [false, false],
    holding: snap.holding === true,
    zone: bodies["target"] ? [bodies["target"][0], bodies["target"][1]] : [1.6, 1.9],
  };
}

const TCP_OFFSET = 0.1375; // the TCP sits this far along the hand's z axis

function tcpOf(pose: Pose): Vec3 {
  const [x, y, z, w, qx, qy, qz] = pose;
  // hand z axis in the world: third column of the rotation matrix
  const zx = 2 * (qx * qz + w * qy);
  const zy = 2 * (qy * qz - w * qx);
  const zz = 1 - 2 * (qx * qx + qy * qy);
  return [x + TCP_OFFSET * zx, y + TCP_OFFSET * zy, z + TCP_OFFSET * zz];
}
