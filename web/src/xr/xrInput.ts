// One XR frame → raw device state: the headset and both controllers' grip-space poses in
// the local-floor reference space, and their buttons and thumbsticks (xr-standard mapping);
// a tracked hand stands in for a controller (./handTracking).

import type { ControllerState, Pose } from "../protocol";
import { xrPose } from "../scene/frames";
import { BUTTON, neutralHand } from "../input/hands";
import type { DeviceFrame } from "../input/hands";
import { handAsController } from "./handTracking";

/** xr-standard gamepad: buttons[0] trigger, [1] squeeze, [3] thumbstick press, [4] A/X, [5] B/Y. */
function handState(source: XRInputSource, frame: XRFrame, space: XRReferenceSpace): ControllerState {
  let pose: Pose | null = null;
  if (source.gripSpace !== undefined) {
    const xr = frame.getPose(source.gripSpace, space);
    if (xr !== undefined && xr !== null) pose = xrPose(xr.transform);
  }
  const pad = source.gamepad;
  if (pad === undefined || pad === null) return { ...neutralHand(pose) };
  const value = (i: number): number => pad.buttons[i]?.value ?? 0;
  const pressed = (i: number): boolean => pad.buttons[i]?.pressed ?? false;
  // Quest controllers put the thumbstick on axes 2/3 (y down); others on 0/1.
  const sx = pad.axes.length >= 4 ? (pad.axes[2] ?? 0) : (pad.axes[0] ?? 0);
  const sy = pad.axes.length >= 4 ? (pad.axes[3] ?? 0) : (pad.axes[1] ?? 0);
  let buttons = 0;
  if (pressed(4)) buttons |= BUTTON.primary;
  if (pressed(5)) buttons |= BUTTON.secondary;
  if (pressed(3)) buttons |= BUTTON.stick;
  if (pressed(6)) buttons |= BUTTON.menu;
  return { pose, grip: value(1), trigger: value(0), stick: [sx, -sy], buttons };
}

export interface XrReading extends DeviceFrame {
  /** Headset position in local-floor (for placing the rig), metres. */
  headsetPosition: { x: number; y: number; z: number } | null;
}

export function readXrFrame(frame: XRFrame, space: XRReferenceSpace): XrReading {
  const viewer = frame.getViewerPose(space);
  const headset = viewer !== undefined && viewer !== null ? xrPose(viewer.transform) : null;
  let left = neutralHand();
  let right = neutralHand();
  let hands = false;
  for (const source of frame.session.inputSources) {
    const hand = source.hand;
    hands ||= hand !== undefined;
    const state = hand !== undefined ? handAsController(hand, frame, space) : handState(source, frame, space);
    if (source.handedness === "left") left = state;
    else if (source.handedness === "right") right = state;
  }
  const p = viewer?.transform.position;
  return {
    source: hands ? "xr_hands" : "xr",
    headset,
    left,
    right,
    headsetPosition: p === undefined ? null : { x: p.x, y: p.y, z: p.z },
  };
}
