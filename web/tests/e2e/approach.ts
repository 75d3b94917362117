// Driving the base up to a box so that the hands' resting point is over it, whatever the
// device: where to stand for a box on a table (shelve: facing +y, the table's near side)
// or at the end of the belt (sort: facing -x), and what is left of the drive at each look,
// in the base frame. touch_by_keys.ts turns it into keys and xr_shelve.ts into thumbsticks.

import type { Pose } from "../../src/protocol";
import { toBase, wrap } from "./observation.js";
import type { Base } from "./observation.js";

export const HANDS_AHEAD = 0.665; // how far ahead of the base the hands rest (m, base frame)
export const HANDS_TOGETHER = 0.2; // how far apart to bring them: both over the box
export const YAW_TOLERANCE = 0.04;
export const TOLERANCE = 0.04;

/** Where to stand for a box waiting on a table: facing +y, the hands over it. */
export function standAtTable(box: Pose): Base {
  return [box[0], box[1] - HANDS_AHEAD, Math.PI / 2];
}

/** Where to stand for a box at the end of the belt: facing -x, the hands over it. */
export function standAtBeltEnd(box: Pose): Base {
  return [box[0] + HANDS_AHEAD, box[1], Math.PI];
}

export interface ApproachLeft {
  /** Heading still to turn (rad, counter-clockwise positive). */
  yawError: number;
  /** Distance still to drive ahead (ex) and to the left (ey), base frame (m). */
  ex: number;
  ey: number;
  /** At the goal within the tolerances. */
  done: boolean;
}

/** What is left of the drive from `base` to `goal`: the heading first, then the position. */
export function approachLeft(base: Base, goal: Base): ApproachLeft {
  const yawError = wrap(goal[2] - base[2]);
  const [ex, ey] = toBase(base, [goal[0], goal[1], 0]);
  const done = Math.abs(yawError) <= YAW_TOLERANCE && Math.abs(ex) <= TOLERANCE && Math.abs(ey) <= TOLERANCE;
  return { yawError, ex, ey, done };
}

/** The two arm targets' distance in the floor plane (world frame, whichever way the robot
 * faces). */
export function handsApart(left: readonly number[], right: readonly number[]): number {
  return Math.hypot((left[0] ?? 0) - (right[0] ?? 0), (left[1] ?? 0) - (right[1] ?? 0));
}
