import { describe, expect, it } from "vitest";
import { FrameMeter, describeReport, quantile } from "../../src/scene/frameMeter";

describe("FrameMeter", () => {
  it("reports frame intervals every window, with its percentiles and the last frame's draw figures", () => {
    const meter = new FrameMeter(1400);
    let report = null;
    let time = 0;
    // 90 intervals of 10 ms, then 10 of 50 ms: 100 intervals, 1.4 s
    for (let i = 0; i < 101 && report === null; i += 1) {
      report = meter.frame(time, 30 + i, 1000, false);
      time += i < 90 ? 10 : 50;
    }
    expect(report).not.toBeNull();
    expect(report?.frames).toBe(100);
    expect(report?.frame_ms_p50).toBe(10);
    expect(report?.frame_ms_p95).toBe(50);
    expect(report?.frame_ms_max).toBe(50);
    expect(report?.draw_calls).toBe(130);
    expect(report?.presenting).toBe(false);
    expect(meter.latest).toEqual(report);
    expect(meter.frame(time, 1, 1, false)).toBeNull(); // a new window has begun
  });

  it("starts a new window on entering a headset", () => {
    const meter = new FrameMeter(100);
    for (let t = 0; t < 90; t += 10) meter.frame(t, 1, 1, false);
    // the jump into the headset is not a frame interval
    expect(meter.frame(500, 1, 1, true)).toBeNull();
    let report = null;
    for (let t = 511; report === null; t += 11) report = meter.frame(t, 2, 2, true);
    expect(report.presenting).toBe(true);
    expect(report.frame_ms_max).toBe(11);
  });

  it("takes nearest-rank quantiles and describes a report in one line", () => {
    expect(quantile([1, 2, 3, 4], 0.5)).toBe(2);
    expect(quantile([1, 2, 3, 4], 0.95)).toBe(4);
    expect(quantile([], 0.5)).toBe(0);
    expect(describeReport(null)).toBe("frame time: measuring");
    const line = describeReport({
      frames: 10, frame_ms_p50: 12.5, frame_ms_p95: 20, frame_ms_max: 30, draw_calls: 42, triangles: 9, presenting: false,
    });
    expect(line).toBe("80 fps, p95 20.0 ms, 42 draws");
  });
});
