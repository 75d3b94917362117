// Comfort in the headset (src/xr/comfort.ts): where the HUD goes, the vignette's strength.

import { describe, expect, it } from "vitest";
import type { Pose } from "../../src/protocol";
import {
  BaseMotionMeter,
  controllerUp,
  hudPlacement,
  offAxisDegrees,
  PARKED_OFFSET,
  vignetteStrength,
} from "../../src/xr/comfort";

const EYES = [0, 1.6, 0] as const;
const S = Math.SQRT1_2;
/** Held low in front, top up (the rest pose). */
const AT_REST: Pose = [-0.2, 1.0, -0.3, 1, 0, 0, 0];
/** Reaching forward to grasp with the palm turned in (90° about the forward axis). */
const AT_WORK: Pose = [-0.2, 1.2, -0.5, S, 0, 0, S];
/** Raised in front of the face, tilted back so its top faces the eyes (a watch gesture). */
const WATCH: Pose = [-0.1, 1.35, -0.3, Math.cos(0.5), Math.sin(0.5), 0, 0];

describe("the headset HUD", () => {
  it("parks well off the forward view when the wrist is not raised", () => {
    for (const left of [AT_REST, AT_WORK, null]) {
      const placed = hudPlacement("wrist", left, EYES);
      expect(placed.where).toBe("parked");
      expect(placed.visible).toBe(true);
      expect(placed.position).toEqual([EYES[0] + PARKED_OFFSET[0], EYES[1] + PARKED_OFFSET[1], EYES[2] + PARKED_OFFSET[2]]);
      expect(offAxisDegrees(EYES, placed.position)).toBeGreaterThan(45);
    }
  });

  it("shows on the wrist when the operator looks at a raised left controller", () => {
    const up = controllerUp(WATCH);
    expect(Math.hypot(...up)).toBeCloseTo(1, 6);
    const placed = hudPlacement("wrist", WATCH, EYES);
    expect(placed.where).toBe("wrist");
    expect(placed.position[1]).toBeCloseTo(WATCH[1] + 0.1, 6);
  });

  it("can be hidden", () => {
    expect(hudPlacement("hidden", WATCH, EYES)).toMatchObject({ visible: false, where: "hidden" });
  });

  it("measures how far off the forward view a point is", () => {
    expect(offAxisDegrees([0, 0, 0], [0, 0, -1])).toBeCloseTo(0, 6);
    expect(offAxisDegrees([0, 0, 0], [1, 0, 0])).toBeCloseTo(90, 6);
    expect(offAxisDegrees([0, 0, 0], [-1, 0, -1])).toBeCloseTo(45, 6);
  });
});

describe("the tunnel vignette", () => {
  const limits = { linear: 0.8, yaw: 1.2 };

  it("is off when the base is still or crawling, full at 60 % of the limits", () => {
    expect(vignetteStrength(0, 0, limits)).toBe(0);
    expect(vignetteStrength(0.04, 0.04, limits)).toBe(0);
    expect(vignetteStrength(0.48, 0, limits)).toBeCloseTo(0.75, 6);
    expect(vignetteStrength(0, -0.72, limits)).toBeCloseTo(0.75, 6);
    expect(vignetteStrength(0.8, 1.2, limits)).toBeCloseTo(0.75, 6);
    const half = vignetteStrength(0.265, 0, limits);
    expect(half).toBeGreaterThan(0.3);
    expect(half).toBeLessThan(0.45);
    expect(vignetteStrength(Number.NaN, 0, limits)).toBe(0);
  });

  it("follows the base's speed and turn rate from successive states", () => {
    const meter = new BaseMotionMeter();
    for (let i = 0; i <= 40; i += 1) meter.update(i * 0.05, 0.5 * i * 0.05, 0, 0.3 * i * 0.05);
    expect(meter.speed).toBeCloseTo(0.5, 3);
    expect(meter.yawRate).toBeCloseTo(0.3, 3);
    meter.update(0, 0, 0, 0); // a new trial: the clock went back
    expect(meter.speed).toBe(0);
    for (let i = 1; i <= 40; i += 1) meter.update(i * 0.05, 0, 0, 0);
    expect(meter.speed).toBe(0);
  });
});
