// A tracked hand (WebXR hand-tracking) read as a controller: the wrist pose is the hand's
// pose, a pinch (thumb tip to index tip) is the trigger that closes the gripper, and a grab
// (middle, ring and little finger curled) is the grip that engages the arm's clutch. The
// server smooths every pose (its One-Euro filter, the session's `input` settings).

import type { ControllerState, Pose } from "../protocol";
import { xrPose } from "../scene/frames";
import { neutralHand } from "../input/hands";

/** Thumb tip to index tip, metres: touching at or below PINCH_CLOSED_M, open at PINCH_OPEN_M. */
export const PINCH_CLOSED_M = 0.015;
export const PINCH_OPEN_M = 0.06;
/** A finger's tip-to-wrist over its knuckle-to-wrist distance: about 2 straight, below 1 curled. */
export const CURL_STRAIGHT = 1.7;
export const CURL_CLOSED = 1.1;
const GRAB_FINGERS = ["middle", "ring", "pinky"] as const;

export type Point = readonly [number, number, number];

const distance = (a: Point, b: Point): number => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
const unit = (v: number): number => Math.min(1, Math.max(0, v));

/** 0 open .. 1 pinched, from the thumb-tip to index-tip distance. */
export function pinchAmount(thumbTip: Point, indexTip: Point): number {
  return unit((PINCH_OPEN_M - distance(thumbTip, indexTip)) / (PINCH_OPEN_M - PINCH_CLOSED_M));
}

/** 0 straight .. 1 curled: one finger, from its tip, its knuckle (proximal phalanx) and the wrist. */
export function curlAmount(tip: Point, knuckle: Point, wrist: Point): number {
  const reach = distance(knuckle, wrist);
  if (reach <= 0) return 0;
  return unit((CURL_STRAIGHT - distance(tip, wrist) / reach) / (CURL_STRAIGHT - CURL_CLOSED));
}

/** The hand's joints a gesture needs, as positions (null: a joint is not tracked). */
export interface HandJoints {
  wrist: Point;
  thumbTip: Point;
  indexTip: Point;
  fingers: { tip: Point; knuckle: Point }[];
}

/** The grab (mean curl of middle, ring and little finger) and the pinch of a hand. */
export function gestures(joints: HandJoints): { grab: number; pinch: number } {
  const curls = joints.fingers.map((f) => curlAmount(f.tip, f.knuckle, joints.wrist));
  const grab = curls.length === 0 ? 0 : curls.reduce((a, b) => a + b, 0) / curls.length;
  return { grab, pinch: pinchAmount(joints.thumbTip, joints.indexTip) };
}

function readJoints(hand: XRHand, frame: XRFrame, space: XRReferenceSpace): { wrist: XRJointPose; joints: HandJoints } | null {
  const at = (name: XRHandJoint): XRJointPose | null => {
    const joint = hand.get(name);
    return joint === undefined ? null : (frame.getJointPose?.(joint, space) ?? null);
  };
  const point = (pose: XRJointPose): Point => [pose.transform.position.x, pose.transform.position.y, pose.transform.position.z];
  const wrist = at("wrist");
  const thumbTip = at("thumb-tip");
  const indexTip = at("index-finger-tip");
  if (wrist === null || thumbTip === null || indexTip === null) return null;
  const fingers: { tip: Point; knuckle: Point }[] = [];
  for (const finger of GRAB_FINGERS) {
    const tip = at(`${finger}-finger-tip`);
    const knuckle = at(`${finger}-finger-phalanx-proximal`);
    if (tip !== null && knuckle !== null) fingers.push({ tip: point(tip), knuckle: point(knuckle) });
  }
  return { wrist, joints: { wrist: point(wrist), thumbTip: point(thumbTip), indexTip: point(indexTip), fingers } };
}

/** A tracked hand as controller state (untracked: no pose, nothing pressed). */
export function handAsController(hand: XRHand, frame: XRFrame, space: XRReferenceSpace): ControllerState {
  const read = readJoints(hand, frame, space);
  if (read === null) return neutralHand();
  const pose: Pose = xrPose(read.wrist.transform);
  const { grab, pinch } = gestures(read.joints);
  return { pose, grip: grab, trigger: pinch, stick: [0, 0], buttons: 0 };
}
