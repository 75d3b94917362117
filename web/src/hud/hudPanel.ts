// The HUD inside the headset: the same lines drawn on a canvas texture on a small panel
// that floats in front of the operator (DOM overlays do not show in immersive-vr).

import * as THREE from "three";
import type { HudLine } from "./hudText";

const WIDTH = 512;
const HEIGHT = 320;
const NOTE_FONT = "20px system-ui, sans-serif";
const NOTE_ROW = 24;
/** The most rows the note (what the trial asks) takes; the rest of it is cut with "…". */
const NOTE_ROWS = 2;

/** `text` broken at spaces into rows no wider than `width` as `measure` measures them, at
 * most `rows` of them (the last one cut with "…" when the text is longer). */
export function wrapText(text: string, width: number, rows: number, measure: (s: string) => number): string[] {
  const out: string[] = [];
  let row = "";
  for (const word of text.split(/\s+/).filter((w) => w !== "")) {
    const wider = row === "" ? word : `${row} ${word}`;
    if (measure(wider) <= width || row === "") {
      row = wider;
      continue;
    }
    out.push(row);
    row = word;
  }
  if (row !== "") out.push(row);
  if (out.length <= rows) return out;
  const kept = out.slice(0, rows);
  let last = `${kept[rows - 1] ?? ""}…`;
  while (measure(last) > width && last.length > 1) last = `${last.slice(0, -2)}…`;
  kept[rows - 1] = last;
  return kept;
}

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

  /** Redraw only when the text changed; `note` (what the trial asks) goes under the title,
   * wrapped. */
  show(title: string, lines: readonly HudLine[], note = ""): void {
    const key = title + note + JSON.stringify(lines);
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
    c.font = NOTE_FONT;
    const noteRows = note === "" ? [] : wrapText(note, WIDTH - 56, NOTE_ROWS, (s) => c.measureText(s).width);
    noteRows.forEach((row, i) => c.fillText(row, 28, 74 + i * NOTE_ROW));
    const top = 86 + noteRows.length * NOTE_ROW;
    const rowHeight = Math.min(38, (HEIGHT - top + 6) / Math.max(1, lines.length));
    lines.forEach((line, i) => {
      const y = top + i * rowHeight;
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
