// A standard-mapping gamepad → the operator's requests (src/input/gamepad.ts).

import { describe, expect, it } from "vitest";
import { padReading } from "../../src/input/gamepad";

function pad(axes: number[], pressed: Record<number, number>): Pick<Gamepad, "axes" | "buttons"> {
  const buttons = Array.from({ length: 17 }, (_, i) => ({ pressed: (pressed[i] ?? 0) > 0, touched: false, value: pressed[i] ?? 0 }));
  return { axes, buttons };
}

describe("gamepad mapping", () => {
  it("drives with the left stick (up is forward) and turns with the right stick", () => {
    const reading = padReading(pad([0.5, -1, 0.3, 0], {}));
    expect(reading.stickL).toEqual([0.5, 1]);
    expect(reading.turn).toBe(0.3);
    expect(reading.active).toBe(true);
  });

  it("ignores a stick inside the dead zone", () => {
    const reading = padReading(pad([0.05, -0.1, 0.11, 0], {}));
    expect(reading.stickL.every((v) => v === 0)).toBe(true); // -0 from a flipped axis is 0
    expect(reading.turn).toBe(0);
    expect(reading.active).toBe(false);
  });

  it("maps the shoulders to grips, triggers to triggers and the d-pad and face buttons to hand motion", () => {
    const reading = padReading(pad([0, 0, 0, 0], { 4: 1, 7: 0.8, 12: 1, 3: 1, 2: 1 }));
    expect(reading.grip).toEqual([1, 0]);
    expect(reading.trigger).toEqual([0, 0.8]);
    expect(reading.move).toEqual([0, 1, -1]);
    expect(reading.squeeze).toBe(1);
  });
});
