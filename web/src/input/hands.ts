// Raw device state as the protocol carries it, and the Input messages built from it.
// Every input device (WebXR, keyboard/mouse, gamepad) ends up here, so the server sees
// one shape whatever the operator holds.

import type { ControllerState, Input, InputSource, Pose } from "../protocol";
import { roundPose } from "../scene/frames";

/** Button bits of ControllerState.buttons. */
export const BUTTON = { primary: 1, secondary: 2, stick: 4, menu: 8 } as const;

export interface DeviceFrame {
  source: InputSource;
  headset: Pose | null;
  left: ControllerState;
  right: ControllerState;
}

export function neutralHand(pose: Pose | null = null): ControllerState {
  return { pose, grip: 0, trigger: 0, stick: [0, 0], buttons: 0 };
}

const clampUnit = (v: number): number => (Number.isFinite(v) ? Math.min(1, Math.max(0, v)) : 0);
const clampAxis = (v: number): number => (Number.isFinite(v) ? Math.min(1, Math.max(-1, v)) : 0);
const r3 = (v: number): number => Math.round(v * 1000) / 1000;

export function cleanHand(hand: ControllerState): ControllerState {
  return {
    pose: hand.pose === null ? null : roundPose(hand.pose),
    grip: r3(clampUnit(hand.grip)),
    trigger: r3(clampUnit(hand.trigger)),
    stick: [r3(clampAxis(hand.stick[0])), r3(clampAxis(hand.stick[1]))],
    buttons: hand.buttons | 0,
  };
}

/** Numbers the inputs of this page: one increasing sequence across reconnects. */
export class InputSequencer {
  private seq = 0;
  last: Input | null = null;

  next(frame: DeviceFrame): Input {
    this.seq += 1;
    const input: Input = {
      type: "input",
      seq: this.seq,
      t_client: performance.now() / 1000,
      source: frame.source,
      headset: frame.headset === null ? null : roundPose(frame.headset),
      left: cleanHand(frame.left),
      right: cleanHand(frame.right),
    };
    this.last = input;
    return input;
  }
}
