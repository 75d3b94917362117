// The HUD inside the headset: the same lines drawn on a canvas texture on a small panel
// that floats in front of the operator (DOM overlays do not show in immersive-vr).

import * as THREE from "three";
import type { HudLine } from "./hudText";

const WIDTH = 512;
const HEIGHT = 320;

export class HudPanel {
  readonly mesh: THREE.Mesh;
  readonly canvas: HTMLCanvasElement;
  private readonly context: CanvasRenderingContext2D;
  private readonly texture: THREE.CanvasTexture;
  private drawn = "";

  constructor() {
    this.canvas = document.createElement("canvas");
    this.canvas.width = WIDTH;
    this.canvas.height = HEIGHT;
    const context = this.canvas.getContext("2d");
    if (context === null) throw new Error("no 2D canvas context for the XR HUD");
    this.context = context;
    this.texture = new THREE.CanvasTexture(this.canvas);
    this.texture.colorSpace = THREE.SRGBColorSpace;
    const material = new THREE.MeshBasicMaterial({
      map: this.texture,
      transparent: true,
      depthTest: false,
    });
    this.mesh = new THREE.Mesh(new THREE.PlaneGeometry(0.48, 0.3), material);
    this.mesh.name = "hud_panel";
    this.mesh.renderOrder = 10;
  }

  /** Redraw only when the text changed. */
  show(title: string, lines: readonly HudLine[]): void {
    const key = title + JSON.stringify(lines);
    if (key === this.drawn) return;
    this.drawn = key;
    const c = this.context;
    c.clearRect(0, 0, WIDTH, HEIGHT);
    c.fillStyle = "rgba(16, 24, 36, 0.82)";
    c.beginPath();
    c.roundRect(4, 4, WIDTH - 8, HEIGHT - 8, 24);
    c.fill();
    c.fillStyle = "#9fd3ff";
    c.font = "bold 30px system-ui, sans-serif";
    c.textBaseline = "alphabetic";
    c.fillText(title, 28, 48);
    c.textBaseline = "middle";
    const rowHeight = Math.min(38, (HEIGHT - 80) / Math.max(1, lines.length));
    lines.forEach((line, i) => {
      const y = 86 + i * rowHeight;
      c.fillStyle = "#c9d4e0";
      c.font = "26px system-ui, sans-serif";
      c.fillText(line.label, 28, y);
      c.fillStyle = line.alert === true ? "#ffb347" : "#ffffff";
      c.font = "bold 28px system-ui, sans-serif";
      c.textAlign = "right";
      c.fillText(line.value, WIDTH - 28, y);
      c.textAlign = "left";
    });
    this.texture.needsUpdate = true;
  }
}
