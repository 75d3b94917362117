// After leaving immersive VR the toolbar is still on top of the 3D view: start a
// practice session with an emulated Meta Quest 3 (IWER), enter VR, leave it, then click
// "Stop session" with the pointer (Playwright clicks only what is topmost at the point).
// IWER puts the canvas back as the viewport's last child, which used to cover the toolbar.
// Prints "RESULT {json}" for the pytest wrapper, which checks the store.
//
//   npm run build:e2e && node build/e2e/tests/e2e/xr_exit_toolbar.js http://127.0.0.1:8000   (in web/)

import path from "node:path";
import { PATIENCE_MS, check, checkDrawn, log, runScript, waitFor } from "./lib.js";
import { startSession, waitForEnd } from "./flow.js";

/** In the page: what the pointer would hit at the centre of each toolbar control. */
function topmostOverToolbar(): { id: string | null; hit: string | null; ok: boolean }[] {
  return [...document.querySelectorAll<HTMLButtonElement>(".toolbar button")].map((button) => {
    const box = button.getBoundingClientRect();
    const hit = document.elementFromPoint(box.x + box.width / 2, box.y + box.height / 2);
    return { id: button.id || button.textContent, hit: hit === null ? null : hit.id || hit.className, ok: hit !== null && button.contains(hit) };
  });
}

await runScript("xr_exit_toolbar", async ({ url, page, artifacts }) => {
  await startSession(page, url, { operatorId: "e2e-xr-exit", query: { emulate: "quest3" }, artifacts });
  const before = await page.evaluate(topmostOverToolbar);
  check(before.every((b) => b.ok), `before VR the toolbar is covered: ${JSON.stringify(before)}`);

  await page.click("#enter-vr"); // the user gesture WebXR needs
  await waitFor(page, (s) => s.teleop?.presenting === true && s.teleop.xr_frames > 5, { what: "the XR session" });
  log("in immersive-vr; leaving it");
  await page.evaluate(() => document.querySelector<HTMLButtonElement>("#enter-vr")?.click()); // "Exit VR"
  await waitFor(page, (s) => s.teleop?.presenting === false, { what: "the XR session to end" });
  await checkDrawn(page, path.join(artifacts, "after-vr.png"));

  const after = await page.evaluate(topmostOverToolbar);
  log(`topmost over the toolbar after VR: ${JSON.stringify(after)}`);
  check(after.every((b) => b.ok), `after VR the toolbar is covered: ${JSON.stringify(after)}`);
  // The trial the stop ends must have begun: the whole flow can take less than the countdown.
  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the countdown to end" });
  await page.click("#stop-session", { timeout: PATIENCE_MS }); // a real pointer click
  await page.click("#stop-confirm", { timeout: PATIENCE_MS }); // and the confirmation
  const end = await waitForEnd(page, 15000);
  const result = { session_id: end.ended.session_id, reason: end.ended.reason, toolbar_after_vr: after };
  console.log(`RESULT ${JSON.stringify(result)}`);
  check(end.ended.reason === "operator_stop", `the session ended ${end.ended.reason}, not operator_stop`);
});
