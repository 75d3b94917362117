// How the teleoperation page draws, for bench/frames.py: one practice session per view
// (desktop at low quality, desktop at normal quality, an emulated Meta Quest 3 in
// immersive-vr), each measured by the page's own frame meter (src/scene/frameMeter.ts)
// over `--windows` report windows of 5 s once the trial runs. Prints "RESULT {json}":
// each view's frame interval percentiles, draw calls and triangles per frame.
//
//   npm run build:e2e && node build/e2e/tests/e2e/frame_budget.js http://127.0.0.1:8000 [windows]   (in web/)

import type { Page } from "playwright-core";
import type { FrameReport } from "../../src/scene/frameMeter";
import { check, log, runScript, waitFor } from "./lib.js";
import { startSession, waitForEnd } from "./flow.js";

interface View {
  name: string;
  query: Record<string, string>;
  headset: boolean;
}

const VIEWS: View[] = [
  { name: "desktop, low quality", query: { quality: "low" }, headset: false },
  { name: "desktop", query: {}, headset: false },
  { name: "headset (emulated Quest 3, both eyes)", query: { emulate: "quest3" }, headset: true },
];

/** The next `windows` frame reports of the page (each a 5 s window). */
async function reports(page: Page, windows: number, presenting: boolean): Promise<FrameReport[]> {
  const seen: FrameReport[] = [];
  let last: FrameReport | null = null;
  while (seen.length < windows) {
    const s = await waitFor(
      page,
      (s) => {
        const report = s.teleop?.frame_report ?? null;
        return report !== null && report.presenting === presenting;
      },
      { what: "a frame report" },
    );
    const report = s.teleop?.frame_report ?? null;
    if (report !== null && JSON.stringify(report) !== JSON.stringify(last)) {
      if (last !== null) seen.push(report); // the first may straddle the start
      last = report;
    }
    await new Promise((resolve) => setTimeout(resolve, 500));
  }
  return seen;
}

await runScript("frame_budget", async ({ url, page, artifacts }) => {
  const windows = Number(process.argv[3] ?? "2");
  check(Number.isInteger(windows) && windows > 0, `windows must be a positive whole number, not ${process.argv[3]}`);
  const results: { view: string; reports: FrameReport[] }[] = [];
  for (const view of VIEWS) {
    await startSession(page, url, { operatorId: "bench-frames", query: view.query, artifacts });
    await waitFor(page, (s) => s.hud?.phase === "running", { what: "the countdown to end" });
    if (view.headset) {
      await page.click("#enter-vr");
      await waitFor(page, (s) => s.teleop?.presenting === true, { what: "the XR session" });
    }
    const measured = await reports(page, windows, view.headset);
    log(`${view.name}: ${JSON.stringify(measured)}`);
    results.push({ view: view.name, reports: measured });
    if (view.headset) {
      await page.evaluate(() => document.querySelector<HTMLButtonElement>("#enter-vr")?.click());
      await waitFor(page, (s) => s.teleop?.presenting === false, { what: "the XR session to end" });
    }
    await page.click("#stop-session");
  await page.click("#stop-confirm"); // the confirmation, with no reason given
    await waitForEnd(page, 15000);
  }
  console.log(`RESULT ${JSON.stringify(results)}`);
});
