// The emulated Meta Quest 3 (IWER) as a scripted operator's device: set the headset and
// controllers from one command and read the page in the same evaluation, and turn the
// scripted operator's decisions into controller poses, grips, triggers and thumbsticks.
// Shared by xr_delivery.ts and xr_task.ts.

import type { EmulatedDevice } from "../../src/xr/emulate";
import type { DebugSnapshot } from "./lib.js";
import { controllerCorrections } from "./operator.js";
import type { Decision, Observation, Vec3 } from "./operator.js";
import type { Seen } from "./delivery.js";

export type Quat = [number, number, number, number];
export type Side = "left" | "right";

/** What to set on one emulated controller (left out: unchanged). */
export interface HandCommand {
  pos?: Vec3;
  quat?: Quat;
  grip?: number;
  trigger?: number;
  stick?: [number, number];
  buttons?: Record<string, number>;
}

export interface DeviceCommand {
  headset?: { pos: Vec3; quat: Quat };
  hands?: Partial<Record<Side, HandCommand>>;
}

export const REST: Record<Side, Vec3> = { left: [-0.2, 1.0, -0.3], right: [0.2, 1.0, -0.3] };
const S = Math.SQRT1_2;
export const PALM_IN: Record<Side, Quat> = { left: [0, 0, S, S], right: [0, 0, -S, S] }; // (x, y, z, w)
export const NEUTRAL: Quat = [0, 0, 0, 1];
/** Standing, looking slightly down at the robot's hands. */
export const HEADSET: NonNullable<DeviceCommand["headset"]> = { pos: [0, 1.6, 0], quat: [Math.sin(-0.2), 0, 0, Math.cos(-0.2)] };

/** Both controllers at rest, nothing pressed. */
export function restingHands(): Record<Side, HandCommand> {
  return {
    left: { pos: REST.left, quat: NEUTRAL, grip: 0, trigger: 0, stick: [0, 0] },
    right: { pos: REST.right, quat: NEUTRAL, grip: 0, trigger: 0, stick: [0, 0] },
  };
}

/** In the page: apply one set of device states to the emulated Quest, read the page. */
export function applyAndObserve(command: DeviceCommand | null): Seen {
  const device: EmulatedDevice | undefined = window.__xrDevice;
  const workcell = window.__workcell;
  if (device === undefined || workcell === undefined) throw new Error("the page has no emulated Quest or no window.__workcell");
  if (command !== null) {
    if (command.headset) {
      device.position.set(...command.headset.pos);
      device.quaternion.set(...command.headset.quat);
    }
    for (const [side, hand] of Object.entries(command.hands ?? {})) {
      const controller = device.controllers[side as Side];
      if (controller === undefined) continue;
      if (hand.pos) controller.position.set(...hand.pos);
      if (hand.quat) controller.quaternion.set(...hand.quat);
      if (hand.grip !== undefined) controller.updateButtonValue("squeeze", hand.grip);
      if (hand.trigger !== undefined) controller.updateButtonValue("trigger", hand.trigger);
      if (hand.stick) controller.updateAxes("thumbstick", hand.stick[0], hand.stick[1]);
      for (const [button, value] of Object.entries(hand.buttons ?? {})) controller.updateButtonValue(button, value);
    }
  }
  return { snap: workcell.snapshot(), bodies: workcell.bodies() };
}

/** Carries the scripted operator's decisions out with the controllers: `act` prepares the
 * next command, which the next `applyAndObserve(device.command)` applies (one round trip
 * per tick); `inputsWithPose` counts the ticks whose last sent input had both poses. */
export class XrDriver {
  command: DeviceCommand | null = null;
  inputsWithPose = 0;
  private readonly ctrl: Record<Side, Vec3> = { left: [...REST.left], right: [...REST.right] };

  act(decision: Decision, obs: Observation, snap: DebugSnapshot): number {
    const corrections = controllerCorrections(obs, decision.targets);
    if (!decision.grip) {
      this.ctrl.left = [...REST.left];
      this.ctrl.right = [...REST.right];
    }
    (["left", "right"] as const).forEach((side, i) => {
      const c = corrections[i];
      const at = this.ctrl[side];
      if (c) this.ctrl[side] = [at[0] + c[0], at[1] + c[1], at[2] + c[2]];
    });
    const grip = decision.grip ? 1 : 0;
    const trigger = decision.trigger ? 1 : 0;
    this.command = {
      hands: {
        left: {
          pos: this.ctrl.left,
          quat: decision.palmsIn ? PALM_IN.left : NEUTRAL,
          grip,
          trigger,
          // xr-standard thumbstick: x right, y down
          stick: [-decision.drive.left, -decision.drive.forward],
        },
        right: {
          pos: this.ctrl.right,
          quat: decision.palmsIn ? PALM_IN.right : NEUTRAL,
          grip,
          trigger,
          stick: [decision.drive.turn, 0],
        },
      },
    };
    const sent = snap.teleop?.last_input;
    if (sent?.source === "xr" && sent.left.pose !== null && sent.right.pose !== null) this.inputsWithPose += 1;
    return 0;
  }
}
