// How the 3D view draws: the interval between animation frames (the frame time a person
// sees), and the WebGL draw calls and triangles of a frame (both eyes in a headset).
// Summarised every few seconds as the protocol's FrameStats, which the teleoperation page
// sends to the server (recorded as a `client_frames` event) and shows in its toolbar.

import type { FrameFigures } from "../protocol";

/** How often a report is made (ms of the animation clock). */
export const REPORT_EVERY_MS = 5000;

export type FrameReport = FrameFigures;

/** The value at quantile `q` of ascending `sorted` (nearest rank). */
export function quantile(sorted: readonly number[], q: number): number {
  if (sorted.length === 0) return 0;
  const rank = Math.min(sorted.length - 1, Math.max(0, Math.ceil(q * sorted.length) - 1));
  return sorted[rank] ?? 0;
}

const round2 = (value: number): number => Math.round(value * 100) / 100;

export class FrameMeter {
  private intervals: number[] = [];
  private lastTime: number | null = null;
  private windowStart: number | null = null;
  private presenting = false;
  /** The last report made (null until the first). */
  latest: FrameReport | null = null;

  constructor(private readonly everyMs = REPORT_EVERY_MS) {}

  /** One frame drawn at `time` (ms, the animation loop's clock) with these figures;
   * returns a report when one is due. Entering or leaving a headset starts a new window
   * (the interval across the switch is not a frame time). */
  frame(time: number, drawCalls: number, triangles: number, presenting: boolean): FrameReport | null {
    if (presenting !== this.presenting) {
      this.presenting = presenting;
      this.intervals = [];
      this.lastTime = null;
      this.windowStart = time;
    }
    if (this.lastTime !== null && time > this.lastTime) this.intervals.push(time - this.lastTime);
    this.lastTime = time;
    this.windowStart ??= time;
    if (time - this.windowStart < this.everyMs || this.intervals.length === 0) return null;
    const sorted = [...this.intervals].sort((a, b) => a - b);
    const report: FrameReport = {
      frames: sorted.length,
      frame_ms_p50: round2(quantile(sorted, 0.5)),
      frame_ms_p95: round2(quantile(sorted, 0.95)),
      frame_ms_max: round2(sorted[sorted.length - 1] ?? 0),
      draw_calls: drawCalls,
      triangles,
      presenting,
    };
    this.intervals = [];
    this.windowStart = time;
    this.latest = report;
    return report;
  }
}

/** The toolbar's one-line summary of a report. */
export function describeReport(report: FrameReport | null): string {
  if (report === null) return "frame time: measuring";
  const fps = report.frame_ms_p50 > 0 ? 1000 / report.frame_ms_p50 : 0;
  return `${fps.toFixed(0)} fps, p95 ${report.frame_ms_p95.toFixed(1)} ms, ${report.draw_calls} draws`;
}
