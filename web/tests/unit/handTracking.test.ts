// Hand gestures read from joint positions, checked on the hand poses Meta recorded for the
// emulated Quest (IWER's default, pinch and point poses) and on hand-made geometry.

import { describe, expect, it } from "vitest";
import { oculusHandConfig } from "iwer/lib/device/XRHandInput.js";
import { curlAmount, gestures, pinchAmount, PINCH_CLOSED_M, PINCH_OPEN_M } from "../../src/xr/handTracking";
import type { HandJoints, Point } from "../../src/xr/handTracking";

function jointsOf(poseId: string): HandJoints {
  const transforms = oculusHandConfig.poses[poseId]?.jointTransforms;
  if (transforms === undefined) throw new Error(`no pose ${poseId}`);
  const at = (name: XRHandJoint): Point => {
    const m = transforms[name].offsetMatrix;
    return [m[12] ?? 0, m[13] ?? 0, m[14] ?? 0];
  };
  return {
    wrist: at("wrist"),
    thumbTip: at("thumb-tip"),
    indexTip: at("index-finger-tip"),
    fingers: (["middle", "ring", "pinky"] as const).map((f) => ({
      tip: at(`${f}-finger-tip`),
      knuckle: at(`${f}-finger-phalanx-proximal`),
    })),
  };
}

describe("hand gestures", () => {
  it("reads an open hand as neither grab nor pinch", () => {
    const { grab, pinch } = gestures(jointsOf("default"));
    expect(grab).toBe(0);
    expect(pinch).toBe(0);
  });

  it("reads a pinch as a closed trigger and no grab", () => {
    const { grab, pinch } = gestures(jointsOf("pinch"));
    expect(pinch).toBe(1);
    expect(grab).toBe(0);
  });

  it("reads three curled fingers as a grab", () => {
    const { grab, pinch } = gestures(jointsOf("point"));
    expect(grab).toBe(1);
    expect(pinch).toBe(0);
  });

  it("scales pinch linearly between its thresholds", () => {
    const middle = (PINCH_OPEN_M + PINCH_CLOSED_M) / 2;
    expect(pinchAmount([0, 0, 0], [middle, 0, 0])).toBeCloseTo(0.5, 9);
    expect(pinchAmount([0, 0, 0], [1, 0, 0])).toBe(0);
  });

  it("measures curl relative to the hand's size", () => {
    // a finger twice as long as its knuckle's reach is straight, at any scale
    for (const scale of [0.5, 1, 2]) {
      expect(curlAmount([0, 0.2 * scale, 0], [0, 0.1 * scale, 0], [0, 0, 0])).toBe(0);
      expect(curlAmount([0, 0.09 * scale, 0], [0, 0.1 * scale, 0], [0, 0, 0])).toBe(1);
    }
    expect(curlAmount([0, 0, 0], [0, 0, 0], [0, 0, 0])).toBe(0);
  });
});
