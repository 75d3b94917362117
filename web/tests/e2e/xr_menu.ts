// The in-VR menu in an emulated Meta Quest 3 (IWER): X opens it, the right thumbstick
// moves the highlight, A chooses. Recenter the view after turning the headset, switch to
// third person, restart the trial (a new trial begins), then stop the session from the
// menu. Prints "RESULT {json}" for the pytest wrapper, which checks the store's events.
//
//   npm run build:e2e && node build/e2e/tests/e2e/xr_menu.js http://127.0.0.1:8000   (in web/)

import path from "node:path";
import type { EmulatedDevice } from "../../src/xr/emulate";
import { check, checkDrawn, log, runScript, sleep, waitFor } from "./lib.js";
import { startSession, waitForEnd } from "./flow.js";

type Side = "left" | "right";

interface DeviceChange {
  side?: Side;
  button?: string;
  value?: number;
  stickY?: number;
  headsetYaw?: number;
}

/** In the page: press (1) or release (0) a button, tilt a stick, turn the headset. */
function device(change: DeviceChange): void {
  const quest: EmulatedDevice | undefined = window.__xrDevice;
  if (quest === undefined) throw new Error("the page has no emulated Quest");
  if (change.headsetYaw !== undefined) quest.quaternion.set(0, Math.sin(change.headsetYaw / 2), 0, Math.cos(change.headsetYaw / 2));
  const controller = change.side === undefined ? undefined : quest.controllers[change.side];
  if (controller === undefined) return;
  if (change.button !== undefined) controller.updateButtonValue(change.button, change.value ?? 0);
  if (change.stickY !== undefined) controller.updateAxes("thumbstick", 0, change.stickY);
}

const ITEMS = ["restart_trial", "recenter_view", "toggle_view", "stop_session", "close"];

await runScript("xr_menu", async ({ url, page, artifacts }) => {
  await startSession(page, url, { operatorId: "e2e-xr-menu", query: { emulate: "quest3" }, artifacts });
  await page.click("#enter-vr");
  await waitFor(page, (s) => s.teleop?.presenting === true && s.teleop.xr_frames > 5, { what: "the XR session" });
  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the trial to run", timeout: 15000 });

  const press = async (side: Side, button: string): Promise<void> => {
    await page.evaluate<void, DeviceChange>(device, { side, button, value: 1 });
    await sleep(150);
    await page.evaluate<void, DeviceChange>(device, { side, button, value: 0 });
    await sleep(150);
  };
  /** Open the menu, move to `item`, choose it. */
  const choose = async (item: string): Promise<void> => {
    await press("left", "x-button");
    await waitFor(page, (s) => s.teleop?.menu.open === true, { what: "X to open the menu" });
    for (let i = 0; i < ITEMS.indexOf(item); i += 1) {
      // xr-standard thumbstick y is down-positive: pushing down moves the highlight down
      await page.evaluate<void, DeviceChange>(device, { side: "right", stickY: 1 });
      await sleep(150);
      await page.evaluate<void, DeviceChange>(device, { side: "right", stickY: 0 });
      await sleep(150);
    }
    const s = await waitFor(page, (s) => s.teleop?.menu.index === ITEMS.indexOf(item), { what: `the highlight on ${item}` });
    check(s.teleop?.menu.open === true, "the menu closed while moving the highlight");
    if (item === "recenter_view") await checkDrawn(page, path.join(artifacts, "xr-menu.png"));
    await press("right", "a-button");
    await waitFor(page, (s) => s.teleop?.menu.open === false, { what: `A to choose ${item}` });
    log(`chose ${item}`);
  };

  // Turn the headset 60° to the left, then recenter: that way becomes forward.
  await page.evaluate<void, DeviceChange>(device, { headsetYaw: Math.PI / 3 });
  await sleep(300);
  await choose("recenter_view");
  let s = await waitFor(page, (s) => Math.abs((s.teleop?.recenter_yaw ?? 0) - Math.PI / 3) < 0.02, { what: "the recentered heading" });
  const sent = s.teleop?.last_input?.headset;
  check(sent !== null && sent !== undefined && Math.abs(sent[5]) < 0.02, `after recentering the headset sent is still turned: ${JSON.stringify(sent)}`);

  await choose("toggle_view");
  s = await waitFor(page, (s) => s.teleop?.view === "third", { what: "the menu to switch to third person" });

  await choose("restart_trial");
  s = await waitFor(page, (s) => s.events.some((e) => e.kind === "trial_started" && e.trial_index === 1), { what: "a new trial after the restart", timeout: 15000 });
  const interrupted = s.events.find((e) => e.kind === "trial_interrupted");
  check(interrupted?.kind === "trial_interrupted" && interrupted.reason === "operator_restart", `the restarted trial ended ${JSON.stringify(interrupted)}`);

  await choose("stop_session");
  const end = await waitForEnd(page, 15000);
  const result = {
    session_id: end.ended.session_id,
    reason: end.ended.reason,
    actions: s.teleop?.actions ?? [],
    recenter_yaw: s.teleop?.recenter_yaw ?? null,
  };
  console.log(`RESULT ${JSON.stringify(result)}`);
  check(end.ended.reason === "operator_stop", `the session ended ${end.ended.reason}, not operator_stop`);
});
