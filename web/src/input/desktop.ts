// Keyboard, mouse and gamepad → the same raw device state a headset reports: two virtual
// controllers held in front of a virtual operator standing at the local-floor origin.
// A virtual controller only moves while its grip is held (that is what moves the arm, by
// the server's clutch); on release it returns to its rest pose, which the clutch ignores.

import * as THREE from "three";
import type { ControllerState, Pose } from "../protocol";
import type { DeviceFrame } from "./hands";
import { readGamepad } from "./gamepad";

export const KEY_MAP: readonly { keys: string; action: string }[] = [
  { keys: "W A S D", action: "drive the base (left stick)" },
  { keys: "Q / E", action: "turn left / right (right stick)" },
  { keys: "Shift", action: "drive slowly" },
  { keys: "G / H (hold)", action: "left / right grip: the arm follows its hand" },
  { keys: "B", action: "toggle both grips held" },
  { keys: "F / J (hold)", action: "close left / right gripper (trigger)" },
  { keys: "N", action: "toggle both grippers closed" },
  { keys: "← ↑ → ↓", action: "move gripped hands left / forward / right / back" },
  { keys: "R / V", action: "move gripped hands up / down" },
  { keys: ", / .", action: "bring gripped hands together / apart" },
  { keys: "Z / X", action: "turn gripped palms inward / outward" },
  { keys: "mouse drag", action: "move gripped hands (wheel: up / down)" },
  { keys: "right drag", action: "look around (the robot's head follows)" },
  { keys: "C", action: "first / third person view" },
  { keys: "P", action: "pause / resume the trial (its clock stops)" },
  { keys: "T", action: "take over from the expert or policy driving / hand back" },
  { keys: "Esc", action: "release everything" },
];

const HEAD_HEIGHT = 1.6;
const REST: Record<"l" | "r", THREE.Vector3> = {
  l: new THREE.Vector3(-0.2, 1.05, -0.35),
  r: new THREE.Vector3(0.2, 1.05, -0.35),
};
const HAND_SPEED = 0.25; // m/s
const SQUEEZE_SPEED = 0.1; // m/s per hand
const ROLL_SPEED = 1.6; // rad/s
const ROLL_LIMIT = Math.PI / 2; // rad: palms facing each other
const MOUSE_METRES_PER_PIXEL = 0.0015;
const WHEEL_METRES_PER_UNIT = 0.0004;
const SLOW = 0.3;

interface VirtualHand {
  position: THREE.Vector3;
  /** Roll about the forward axis; positive turns the palm inward. */
  roll: number;
}

function typing(target: EventTarget | null): boolean {
  return (
    target instanceof HTMLInputElement ||
    target instanceof HTMLTextAreaElement ||
    target instanceof HTMLSelectElement
  );
}

export class DesktopInput {
  private readonly down = new Set<string>();
  /** Keys pressed since the last read... */
  private readonly unread = new Set<string>();
  /** ...and of those, the ones already let go: a tap shorter than a frame still counts as
   * held for one read, so on a slow page (a frame every few hundred ms) a short tap moves
   * the robot a little instead of being lost between two frames. */
  private readonly tapped = new Set<string>();
  private latchedGrip = false;
  private latchedTrigger = false;
  private readonly hands: Record<"l" | "r", VirtualHand> = {
    l: { position: REST.l.clone(), roll: 0 },
    r: { position: REST.r.clone(), roll: 0 },
  };
  private look = { yaw: 0, pitch: -0.3 };
  private drag: { button: number; x: number; y: number } | null = null;
  private pendingMouse = new THREE.Vector3();
  private lastPadActive = -Infinity;
  /** Pressed view toggle (C) since the last read. */
  viewToggleRequested = false;
  /** P was pressed: the page pauses or resumes the trial. */
  pauseToggleRequested = false;
  /** T was pressed: the page takes over from the session's driver or hands back. */
  driveToggleRequested = false;
  /** Wheel turned without a grip held (the page zooms the camera). */
  onZoom: ((delta: number) => void) | null = null;
  private readonly cleanup: (() => void)[] = [];

  constructor(surface: HTMLElement) {
    const on = <K extends keyof WindowEventMap>(
      target: Window | HTMLElement,
      type: K,
      handler: (event: WindowEventMap[K]) => void,
      options?: AddEventListenerOptions,
    ): void => {
      target.addEventListener(type, handler as EventListener, options);
      this.cleanup.push(() => target.removeEventListener(type, handler as EventListener));
    };
    on(window, "keydown", (e) => this.keyDown(e));
    on(window, "keyup", (e) => this.keyUp(e.code));
    on(window, "blur", () => this.releaseAll());
    on(surface, "contextmenu", (e) => e.preventDefault());
    on(surface, "mousedown", (e) => {
      this.drag = { button: e.button, x: e.clientX, y: e.clientY };
      surface.focus();
    });
    on(window, "mouseup", () => (this.drag = null));
    on(window, "mousemove", (e) => this.mouseMove(e));
    on(surface, "wheel", (e) => this.wheel(e), { passive: false });
  }

  dispose(): void {
    for (const undo of this.cleanup) undo();
  }

  /** Keys currently held (for the on-screen key map). */
  get held(): ReadonlySet<string> {
    return this.down;
  }

  get gripsLatched(): boolean {
    return this.latchedGrip;
  }

  get triggersLatched(): boolean {
    return this.latchedTrigger;
  }

  /** Advance the virtual devices by `dt` seconds and read them. */
  read(dt: number): DeviceFrame {
    const pad = readGamepad();
    const now = performance.now();
    if (pad?.active === true) this.lastPadActive = now;
    const key = (code: string): number => (this.down.has(code) || this.tapped.has(code) ? 1 : 0);
    const slow = key("ShiftLeft") + key("ShiftRight") > 0 ? SLOW : 1;

    const grip: [number, number] = [
      Math.max(key("KeyG"), this.latchedGrip ? 1 : 0, pad?.grip[0] ?? 0),
      Math.max(key("KeyH"), this.latchedGrip ? 1 : 0, pad?.grip[1] ?? 0),
    ];
    const trigger: [number, number] = [
      Math.max(key("KeyF"), this.latchedTrigger ? 1 : 0, pad?.trigger[0] ?? 0),
      Math.max(key("KeyJ"), this.latchedTrigger ? 1 : 0, pad?.trigger[1] ?? 0),
    ];
    const stickL: [number, number] = [
      clampAxis((key("KeyD") - key("KeyA")) * slow + (pad?.stickL[0] ?? 0)),
      clampAxis((key("KeyW") - key("KeyS")) * slow + (pad?.stickL[1] ?? 0)),
    ];
    const turn = clampAxis((key("KeyE") - key("KeyQ")) * slow + (pad?.turn ?? 0));

    const move = new THREE.Vector3(
      key("ArrowRight") - key("ArrowLeft") + (pad?.move[0] ?? 0),
      key("KeyR") - key("KeyV") + (pad?.move[1] ?? 0),
      key("ArrowDown") - key("ArrowUp") + (pad?.move[2] ?? 0),
    ).multiplyScalar(HAND_SPEED * dt * slow);
    move.add(this.pendingMouse);
    this.pendingMouse.set(0, 0, 0);
    const squeeze = (key("Comma") - key("Period") + (pad?.squeeze ?? 0)) * SQUEEZE_SPEED * dt * slow;
    const roll = (key("KeyZ") - key("KeyX") + (pad?.roll ?? 0)) * ROLL_SPEED * dt * slow;

    (["l", "r"] as const).forEach((side, i) => {
      const hand = this.hands[side];
      if ((grip[i] ?? 0) < 0.5) {
        hand.position.copy(REST[side]);
        hand.roll = 0;
        return;
      }
      hand.position.add(move);
      hand.position.x += side === "l" ? squeeze : -squeeze;
      hand.roll = Math.max(-ROLL_LIMIT, Math.min(ROLL_LIMIT, hand.roll + roll));
    });

    const source = now - this.lastPadActive < 2000 ? "gamepad" : "desktop";
    this.unread.clear(); // this read saw every key pressed or tapped since the last
    this.tapped.clear();
    return {
      source,
      headset: this.headsetPose(),
      left: this.controller("l", grip[0], trigger[0], stickL),
      right: this.controller("r", grip[1], trigger[1], [turn, 0]),
    };
  }

  private controller(
    side: "l" | "r",
    grip: number,
    trigger: number,
    stick: [number, number],
  ): ControllerState {
    const hand = this.hands[side];
    // Palm inward: the left hand rolls counter-clockwise about -z (as seen by the
    // operator), i.e. +roll about +z; the right hand mirrors it.
    const angle = side === "l" ? hand.roll : -hand.roll;
    const q = new THREE.Quaternion().setFromAxisAngle(new THREE.Vector3(0, 0, 1), angle);
    const p = hand.position;
    const pose: Pose = [p.x, p.y, p.z, q.w, q.x, q.y, q.z];
    return { pose, grip, trigger, stick, buttons: 0 };
  }

  private headsetPose(): Pose {
    const q = new THREE.Quaternion().setFromEuler(
      new THREE.Euler(this.look.pitch, this.look.yaw, 0, "YXZ"),
    );
    return [0, HEAD_HEIGHT, 0, q.w, q.x, q.y, q.z];
  }

  private gripping(): boolean {
    return (
      this.latchedGrip || this.down.has("KeyG") || this.down.has("KeyH") || (readGamepad()?.grip.some((g) => g > 0.5) ?? false)
    );
  }

  private keyUp(code: string): void {
    this.down.delete(code);
    if (this.unread.has(code)) this.tapped.add(code);
  }

  private releaseAll(): void {
    this.down.clear();
    this.unread.clear();
    this.tapped.clear();
  }

  private keyDown(event: KeyboardEvent): void {
    if (typing(event.target)) return;
    if (event.code.startsWith("Arrow") || event.code === "Space") event.preventDefault();
    if (event.repeat) return;
    this.down.add(event.code);
    this.unread.add(event.code);
    switch (event.code) {
      case "KeyB":
        this.latchedGrip = !this.latchedGrip;
        break;
      case "KeyN":
        this.latchedTrigger = !this.latchedTrigger;
        break;
      case "KeyC":
        this.viewToggleRequested = true;
        break;
      case "KeyP":
        this.pauseToggleRequested = true;
        break;
      case "KeyT":
        this.driveToggleRequested = true;
        break;
      case "Escape":
        this.latchedGrip = false;
        this.latchedTrigger = false;
        this.releaseAll();
        break;
      default:
        break;
    }
  }

  private mouseMove(event: MouseEvent): void {
    const drag = this.drag;
    if (drag === null) return;
    const dx = event.clientX - drag.x;
    const dy = event.clientY - drag.y;
    drag.x = event.clientX;
    drag.y = event.clientY;
    if (drag.button === 2) {
      this.look.yaw = Math.max(-1.5, Math.min(1.5, this.look.yaw - dx * 0.004));
      this.look.pitch = Math.max(-1.1, Math.min(0.7, this.look.pitch - dy * 0.004));
    } else if (drag.button === 0 && this.gripping()) {
      this.pendingMouse.x += dx * MOUSE_METRES_PER_PIXEL;
      this.pendingMouse.z += dy * MOUSE_METRES_PER_PIXEL;
    }
  }

  private wheel(event: WheelEvent): void {
    event.preventDefault();
    if (this.gripping()) {
      this.pendingMouse.y -= event.deltaY * WHEEL_METRES_PER_UNIT;
    } else {
      this.onZoom?.(event.deltaY);
    }
  }
}

function clampAxis(v: number): number {
  return Math.max(-1, Math.min(1, v));
}
