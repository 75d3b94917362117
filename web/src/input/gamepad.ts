// The Gamepad API (outside XR): a standard-mapping pad read once per frame.

export interface PadReading {
  stickL: [number, number];
  turn: number;
  grip: [number, number];
  trigger: [number, number];
  /** Hand motion requested: x right, y up, z back (local-floor), unit rates. */
  move: [number, number, number];
  /** Hands together (+) / apart (-). */
  squeeze: number;
  /** Palms in (+) / out (-). */
  roll: number;
  active: boolean;
}

const DEAD = 0.12;

function axis(pad: Pick<Gamepad, "axes">, i: number): number {
  const v = pad.axes[i] ?? 0;
  return Math.abs(v) < DEAD ? 0 : v;
}

function button(pad: Pick<Gamepad, "buttons">, i: number): number {
  return pad.buttons[i]?.value ?? 0;
}

/** The first connected standard gamepad, if any. */
export function readGamepad(): PadReading | null {
  if (typeof navigator.getGamepads !== "function") return null;
  const pad = Array.from(navigator.getGamepads()).find(
    (p): p is Gamepad => p !== null && p.connected && p.mapping === "standard",
  );
  return pad === undefined ? null : padReading(pad);
}

/** What a standard-mapping pad's axes and buttons ask for. */
export function padReading(pad: Pick<Gamepad, "axes" | "buttons">): PadReading {
  const reading: PadReading = {
    stickL: [axis(pad, 0), -axis(pad, 1)],
    turn: axis(pad, 2),
    grip: [button(pad, 4), button(pad, 5)],
    trigger: [button(pad, 6), button(pad, 7)],
    move: [
      button(pad, 15) - button(pad, 14),
      button(pad, 3) - button(pad, 0),
      button(pad, 13) - button(pad, 12),
    ],
    squeeze: button(pad, 2) - button(pad, 1),
    roll: -axis(pad, 3),
    active: false,
  };
  reading.active =
    reading.stickL.some((v) => v !== 0) ||
    reading.turn !== 0 ||
    [...reading.grip, ...reading.trigger, ...reading.move].some((v) => v > 0.05 || v < -0.05) ||
    reading.squeeze !== 0 ||
    reading.roll !== 0;
  return reading;
}
