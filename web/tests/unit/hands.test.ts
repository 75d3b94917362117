// Raw device state → Input messages (src/input/hands.ts): clamped, rounded, numbered.

import { describe, expect, it } from "vitest";
import { cleanHand, InputSequencer, neutralHand } from "../../src/input/hands";

describe("input mapping", () => {
  it("clamps grip and trigger to [0, 1] and the stick to [-1, 1], non-finite to 0", () => {
    const hand = cleanHand({ pose: null, grip: 1.7, trigger: Number.NaN, stick: [-3, 0.12345], buttons: 5.9 });
    expect(hand).toEqual({ pose: null, grip: 1, trigger: 0, stick: [-1, 0.123], buttons: 5 });
  });

  it("numbers inputs one by one and rounds what they carry", () => {
    const sequencer = new InputSequencer();
    const left = { ...neutralHand([0.123456, 1, -0.5, 1, 0, 0, 0]), grip: 0.66666 };
    const frame = { source: "desktop", headset: null, left, right: neutralHand() } as const;
    const first = sequencer.next(frame);
    const second = sequencer.next(frame);
    expect([first.seq, second.seq]).toEqual([1, 2]);
    expect(second.type).toBe("input");
    expect(second.left.grip).toBe(0.667);
    expect(second.left.pose?.[0]).toBeCloseTo(0.1235, 3);
    expect(sequencer.last).toBe(second);
  });
});
