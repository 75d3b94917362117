// End to end in an emulated Meta Quest 3 (IWER): set up a practice session, enter
// immersive-vr, drive the base with the left thumbstick, toggle the view with B, then
// a scripted operator takes both grips, moves the controllers, closes both triggers and
// delivers the box. Prints "RESULT {json}" for the pytest wrapper, which checks the store.
//
//   npm run build:e2e && node build/e2e/tests/e2e/xr_delivery.js http://127.0.0.1:8000   (in web/)

import { writeFileSync } from "node:fs";
import path from "node:path";
import { check, checkDrawn, imageStats, log, runScript, sleep, waitFor } from "./lib.js";
import { ScriptedOperator } from "./operator.js";
import { startSession } from "./flow.js";
import { checkDelivered, deliver, deliveryResult } from "./delivery.js";
import { HEADSET, XrDriver, applyAndObserve, restingHands } from "./xr_device.js";
import type { DeviceCommand } from "./xr_device.js";

const TICK_MS = 20;

await runScript("xr_delivery", async ({ url, page, artifacts }) => {
  await startSession(page, url, { operatorId: "e2e-xr", query: { emulate: "quest3" }, artifacts });
  check(await page.evaluate(() => window.__xrDevice !== undefined), "the emulated Quest 3 is not installed");
  await page.waitForSelector("#hud dl");
  await checkDrawn(page, path.join(artifacts, "hud-desktop.png"), page.locator("#hud"));

  // Enter immersive VR (a click is the user gesture WebXR needs).
  await page.click("#enter-vr");
  let s = await waitFor(page, (s) => s.teleop?.presenting === true && s.teleop.xr_frames > 5, { what: "the XR session" });
  log(`in immersive-vr, view ${s.teleop?.view}`);
  const resting: DeviceCommand = { headset: HEADSET, hands: restingHands() };
  await page.evaluate(applyAndObserve, resting);

  // B toggles first/third person; toggle twice and check both views are drawn.
  await sleep(600);
  await checkDrawn(page, path.join(artifacts, "xr-first-person.png"));
  await page.evaluate(applyAndObserve, { hands: { right: { buttons: { "b-button": 1 } } } });
  await waitFor(page, (s) => s.teleop?.view === "third", { what: "B to switch to third person" });
  await page.evaluate(applyAndObserve, { hands: { right: { buttons: { "b-button": 0 } } } });
  await sleep(600);
  await checkDrawn(page, path.join(artifacts, "xr-third-person.png"));
  await page.evaluate(applyAndObserve, { hands: { right: { buttons: { "b-button": 1 } } } });
  await waitFor(page, (s) => s.teleop?.view === "first", { what: "B to switch back to first person" });
  await page.evaluate(applyAndObserve, { hands: { right: { buttons: { "b-button": 0 } } } });

  // The HUD panel is parked off the forward view while the hands rest or work; a left
  // thumbstick press hides it and another brings it back.
  s = await waitFor(page, (s) => s.teleop?.hud.where === "parked", { what: "the HUD parked off the view" });
  const hudAngle = s.teleop?.hud.off_axis_deg ?? 0;
  log(`XR HUD parked ${hudAngle.toFixed(1)} degrees off the robot's forward view`);
  check(hudAngle > 45 && s.teleop?.hud.visible === true, `the XR HUD is ${hudAngle.toFixed(1)} degrees off the view (wanted > 45)`);
  for (const mode of ["hidden", "wrist"] as const) {
    await page.evaluate(applyAndObserve, { hands: { left: { buttons: { thumbstick: 1 } } } });
    await waitFor(page, (s) => s.teleop?.hud.mode === mode, { what: `the left thumbstick press to make the HUD ${mode}` });
    await page.evaluate(applyAndObserve, { hands: { left: { buttons: { thumbstick: 0 } } } });
  }
  s = await waitFor(page, (s) => s.teleop?.hud.visible === true, { what: "the HUD to show again" });
  check(s.teleop?.comfort.vignette === 0, "the vignette is on while the base stands still");

  // The trial clock runs once the countdown is over; the HUD panel in the headset shows it.
  s = await waitFor(page, (s) => s.hud?.phase === "running", { what: "the countdown to end" });
  await sleep(300);
  const panel = await page.evaluate(() => window.__workcell?.capture("hud_panel") ?? null);
  check(panel !== null && panel.startsWith("data:image/png"), "no XR HUD panel");
  writeFileSync(path.join(artifacts, "xr-hud-panel.png"), Buffer.from(panel.split(",")[1] ?? "", "base64"));
  const panelStats = await imageStats(page, panel);
  log(`XR HUD panel: luminance variance ${panelStats.variance.toFixed(1)}, ${panelStats.colours} colours`);
  check(panelStats.variance > 100, "the XR HUD panel is blank");
  const start = s.state;
  const operator = new ScriptedOperator();
  const device = new XrDriver();
  const run = await deliver(page, artifacts, operator, {
    prefix: "xr",
    tickMs: TICK_MS,
    debugEveryMs: 1000,
    adaptLead: true,
    look: () => page.evaluate(applyAndObserve, device.command),
    act: (decision, obs, snap) => Promise.resolve(device.act(decision, obs, snap)),
    debug: (decision, obs, snap) => {
      const box = obs.boxes.find((b) => b.name === operator.box);
      const sent = snap.teleop?.last_input;
      return `drive=${JSON.stringify(decision.drive)} box=${box?.pos.map((v) => v.toFixed(3))} holding=${obs.holding} following=${obs.following} input=${JSON.stringify(sent?.left.stick)} seq=${sent?.seq} applied=${snap.state?.input_seq}`;
    },
  });
  await checkDrawn(page, path.join(artifacts, "xr-end.png"));
  // Driving in first person narrowed the view; standing still it is clear again.
  const still = await waitFor(page, (s) => s.teleop?.comfort.vignette === 0, { what: "the vignette to clear" });
  const peak = still.teleop?.comfort.vignette_peak ?? 0;
  log(`tunnel vignette: peak ${peak.toFixed(2)} while driving, ${still.teleop?.comfort.vignette} standing still`);
  check(peak > 0.3, `the tunnel vignette peaked at ${peak.toFixed(2)} while the base drove (wanted > 0.3)`);

  // Leave VR: the desktop end-of-campaign screen and the HUD are drawn.
  await page.evaluate(() => document.querySelector<HTMLButtonElement>("#enter-vr")?.click());
  await waitFor(page, (s) => s.teleop?.presenting === false, { what: "the XR session to end" });
  await page.waitForSelector("#end-screen.campaign-end");
  await checkDrawn(page, path.join(artifacts, "end-screen.png"), page.locator("#end-screen"));
  await checkDrawn(page, path.join(artifacts, "view-after.png"));

  const result = {
    ...deliveryResult(run),
    xr_inputs_with_pose: device.inputsWithPose,
    input_seq_applied: start?.input_seq ?? null,
    stale_states_dropped: run.end.stats.stale,
    hud_off_axis_deg: hudAngle,
    vignette_peak: peak,
  };
  console.log(`RESULT ${JSON.stringify(result)}`);
  checkDelivered(run, "thumbstick");
});
