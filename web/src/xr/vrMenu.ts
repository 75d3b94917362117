// The in-VR menu: opened with X on the left controller, the right thumbstick moves the
// highlight, A (or the right trigger) chooses, X or B closes. While it is open the sticks
// do not drive. Each choice is an action the page carries out (and the server records).
// "Stop session" asks to be chosen a second time ("Confirm stop") before it stops.

import * as THREE from "three";

export type MenuItem =
  | "restart_trial"
  | "recenter_view"
  | "toggle_view"
  | "toggle_turn"
  | "pause"
  | "take_over"
  | "stop_session"
  | "close";
export const MENU_ITEMS: readonly MenuItem[] = [
  "restart_trial",
  "recenter_view",
  "toggle_view",
  "toggle_turn",
  "pause",
  "take_over",
  "stop_session",
  "close",
];

const LABELS: Record<MenuItem, string> = {
  restart_trial: "Restart trial",
  recenter_view: "Recenter view",
  toggle_view: "Switch view",
  toggle_turn: "Switch turning",
  pause: "Pause",
  take_over: "Take over",
  stop_session: "Stop session",
  close: "Close menu",
};

/** Buttons and stick as the menu reads them, one frame. */
export interface MenuInput {
  open: boolean; // X on the left controller
  choose: boolean; // A, or the right trigger
  back: boolean; // B
  stickY: number; // right thumbstick, up positive
}

/** The menu's logic, free of drawing: edge-triggered on buttons and stick flicks. */
export class MenuState {
  open = false;
  index = 0;
  private last: MenuInput = { open: false, choose: false, back: false, stickY: 0 };

  /** Open the menu again with the highlight where it was (a choice that asks to be
   * confirmed). */
  reopen(): void {
    this.open = true;
  }

  /** One frame of input; returns the item chosen this frame, if any. */
  update(input: MenuInput): MenuItem | null {
    const last = this.last;
    this.last = input;
    if (input.open && !last.open) {
      this.open = !this.open;
      this.index = 0;
      return null;
    }
    if (!this.open) return null;
    if (input.back && !last.back) {
      this.open = false;
      return null;
    }
    const flick = (y: number): number => (y > 0.6 ? 1 : y < -0.6 ? -1 : 0);
    const step = flick(input.stickY);
    if (step !== 0 && step !== flick(last.stickY)) {
      this.index = (this.index - step + MENU_ITEMS.length) % MENU_ITEMS.length;
    }
    if (input.choose && !last.choose) {
      const item = MENU_ITEMS[this.index] ?? "close";
      this.open = false;
      return item;
    }
    return null;
  }
}

const WIDTH = 512;
const ROW = 64;

export class VrMenu {
  readonly state = new MenuState();
  readonly mesh: THREE.Mesh;
  private readonly context: CanvasRenderingContext2D;
  private readonly texture: THREE.CanvasTexture;
  private drawn = "";

  constructor() {
    const canvas = document.createElement("canvas");
    canvas.width = WIDTH;
    canvas.height = ROW * MENU_ITEMS.length + 24;
    const context = canvas.getContext("2d");
    if (context === null) throw new Error("no 2D canvas context for the VR menu");
    this.context = context;
    this.texture = new THREE.CanvasTexture(canvas);
    this.texture.colorSpace = THREE.SRGBColorSpace;
    const material = new THREE.MeshBasicMaterial({ map: this.texture, transparent: true, depthTest: false });
    const height = (0.4 * canvas.height) / WIDTH;
    this.mesh = new THREE.Mesh(new THREE.PlaneGeometry(0.4, height), material);
    this.mesh.name = "vr_menu";
    this.mesh.renderOrder = 30;
    this.mesh.visible = false;
  }

  /** Draw the items with the highlight (only when something changed); the toggles are
   * labelled with what choosing them switches to. */
  draw(
    viewLabel: string,
    turnLabel = LABELS.toggle_turn,
    pauseLabel = LABELS.pause,
    stopLabel = LABELS.stop_session,
    driveLabel = LABELS.take_over,
  ): void {
    const key = `${this.state.index}|${viewLabel}|${turnLabel}|${pauseLabel}|${stopLabel}|${driveLabel}`;
    if (key === this.drawn) return;
    this.drawn = key;
    const c = this.context;
    const { width, height } = c.canvas;
    c.clearRect(0, 0, width, height);
    c.fillStyle = "rgba(16, 24, 36, 0.9)";
    c.beginPath();
    c.roundRect(4, 4, width - 8, height - 8, 20);
    c.fill();
    MENU_ITEMS.forEach((item, i) => {
      const y = 12 + i * ROW;
      if (i === this.state.index) {
        c.fillStyle = "#2f6fb0";
        c.fillRect(16, y, width - 32, ROW - 8);
      }
      c.fillStyle = "#ffffff";
      c.font = "bold 30px system-ui, sans-serif";
      c.textBaseline = "middle";
      const labels: Partial<Record<MenuItem, string>> = {
        toggle_view: viewLabel,
        toggle_turn: turnLabel,
        pause: pauseLabel,
        take_over: driveLabel,
        stop_session: stopLabel,
      };
      const label = labels[item] ?? LABELS[item];
      c.fillText(label, 36, y + (ROW - 8) / 2);
    });
    this.texture.needsUpdate = true;
  }
}
