// Keyboard → the virtual controllers (src/input/desktop.ts), with window events in node.

import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { DesktopInput } from "../../src/input/desktop";

class NotAField {}

function press(code: string, type: "keydown" | "keyup" = "keydown"): void {
  window.dispatchEvent(Object.assign(new Event(type), { code, repeat: false }));
}

describe("desktop input mapping", () => {
  let input: DesktopInput;

  beforeEach(() => {
    vi.stubGlobal("window", new EventTarget());
    vi.stubGlobal("navigator", {});
    for (const name of ["HTMLInputElement", "HTMLTextAreaElement", "HTMLSelectElement"]) vi.stubGlobal(name, NotAField);
    const surface = Object.assign(new EventTarget(), { focus: () => undefined });
    input = new DesktopInput(surface as unknown as HTMLElement);
  });

  afterEach(() => {
    input.dispose();
    vi.unstubAllGlobals();
  });

  it("drives with W A S D on the left stick and turns with Q / E on the right", () => {
    press("KeyW");
    press("KeyE");
    const frame = input.read(1 / 60);
    expect(frame.source).toBe("desktop");
    expect(frame.left.stick).toEqual([0, 1]);
    expect(frame.right.stick).toEqual([1, 0]);
    press("KeyW", "keyup");
    expect(input.read(1 / 60).left.stick).toEqual([0, 0]);
  });

  it("counts a tap shorter than a frame as held for the next read only", () => {
    press("KeyS");
    press("ShiftLeft");
    press("KeyS", "keyup"); // let go before the page drew a frame
    press("ShiftLeft", "keyup");
    expect(input.read(0.3).left.stick).toEqual([0, -0.3]); // slowly backward, once
    expect(input.read(0.3).left.stick).toEqual([0, 0]);
    press("KeyW");
    expect(input.read(0.3).left.stick).toEqual([0, 1]);
    press("KeyW", "keyup"); // held across a read, then let go: no extra read
    expect(input.read(0.3).left.stick).toEqual([0, 0]);
    press("KeyD");
    press("Escape"); // Esc lets go of everything, taps included
    expect(input.read(0.3).left.stick).toEqual([0, 0]);
  });

  it("moves a hand only while its grip is held, and springs it back on release", () => {
    const rest = input.read(0.1).left.pose;
    press("KeyG");
    press("ArrowUp");
    const moved = input.read(0.1);
    expect(moved.left.grip).toBe(1);
    expect(moved.left.pose?.[2]).toBeCloseTo((rest?.[2] ?? 0) - 0.025, 6); // forward is -z
    expect(moved.right.pose).toEqual(input.read(0).right.pose); // not gripped: stays at rest
    press("KeyG", "keyup");
    expect(input.read(0.1).left.pose).toEqual(rest);
  });

  it("closes the grippers with F / J and toggles both with N; Esc releases everything", () => {
    press("KeyF");
    expect(input.read(0).left.trigger).toBe(1);
    press("KeyF", "keyup");
    press("KeyN");
    const latched = input.read(0);
    expect([latched.left.trigger, latched.right.trigger]).toEqual([1, 1]);
    press("Escape");
    const released = input.read(0);
    expect([released.left.trigger, released.right.trigger]).toEqual([0, 0]);
  });
});
