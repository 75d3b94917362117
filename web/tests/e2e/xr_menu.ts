// The in-VR menu in an emulated Meta Quest 3 (IWER): X opens it, the right thumbstick
// moves the highlight, A chooses. Recenter the view after turning the headset, switch to
// third person, restart the trial (a new trial begins), switch to snap turns and flick the
// right stick (the server turns the base 30 degrees while the view is blacked out), pause
// and resume, then stop the session from the menu (chosen twice: the second confirms). Prints "RESULT {json}" for the pytest wrapper, which checks
// the store's events.
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
  stickX?: number;
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
  if (change.stickY !== undefined || change.stickX !== undefined) {
    controller.updateAxes("thumbstick", change.stickX ?? 0, change.stickY ?? 0);
  }
}

/** In the page: the robot base's heading as drawn (radians). */
function baseYaw(): number {
  const base = window.__workcell?.bodies()["base"];
  if (base === undefined) throw new Error("no base drawn");
  const [, , , w, x, y, z] = base;
  return Math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
}

const ITEMS = ["restart_trial", "recenter_view", "toggle_view", "toggle_turn", "pause", "take_over", "stop_session", "close"];

await runScript("xr_menu", async ({ url, page, artifacts }) => {
  await startSession(page, url, { operatorId: "e2e-xr-menu", query: { emulate: "quest3" }, artifacts });
  await page.click("#enter-vr");
  await waitFor(page, (s) => s.teleop?.presenting === true && s.teleop.xr_frames > 5, { what: "the XR session" });
  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the trial to run" });

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
    if (item === "stop_session") {
      // the first choice asks: the menu stays open on "Confirm stop"; A again stops
      await waitFor(page, (s) => s.teleop?.menu.open === true && s.teleop.menu.stop_armed, { what: "the menu to ask to confirm the stop" });
      await press("right", "a-button");
    }
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
  s = await waitFor(page, (s) => s.events.some((e) => e.kind === "trial_started" && e.trial_index === 1), { what: "a new trial after the restart" });
  const interrupted = s.events.find((e) => e.kind === "trial_interrupted");
  check(interrupted?.kind === "trial_interrupted" && interrupted.reason === "operator_restart", `the restarted trial ended ${JSON.stringify(interrupted)}`);

  // Snap turns: a flick of the right stick turns the base about 30°, the view blacked out.
  await choose("toggle_turn");
  await waitFor(page, (s) => s.teleop?.comfort.turn === "snap", { what: "the menu to switch to snap turns" });
  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the new trial to run" });
  const before = await page.evaluate(baseYaw);
  await page.evaluate<void, DeviceChange>(device, { side: "right", stickX: 0.9 });
  await waitFor(page, (s) => s.teleop?.comfort.blackout === true, { what: "the view to black out while the base turns", every: 20 });
  s = await waitFor(page, (s) => s.teleop?.comfort.snaps === 1 && !s.teleop.comfort.blackout, { what: "the snap turn to end" });
  await page.evaluate<void, DeviceChange>(device, { side: "right", stickX: 0 });
  await sleep(300);
  const after = await page.evaluate(baseYaw);
  const turned = Math.atan2(Math.sin(after - before), Math.cos(after - before));
  log(`snap turn: the base turned ${((turned * 180) / Math.PI).toFixed(1)} degrees, the stick held all along`);
  check(Math.abs(turned + Math.PI / 6) < 0.05, `one flick to the right turned the base ${turned.toFixed(3)} rad (wanted ${(-Math.PI / 6).toFixed(3)})`);
  check(s.teleop?.comfort.snaps === 1, "holding the stick made more than one snap");

  // Pause from the menu: the trial's clock stands still until "Resume" (the same item).
  await choose("pause");
  s = await waitFor(page, (s) => s.teleop?.paused === true, { what: "the menu to pause the trial" });
  const pausedAt = s.state?.t_sim ?? 0;
  await sleep(1000);
  s = await waitFor(page, (s) => s.state !== null, { what: "a state" });
  check(s.state?.t_sim === pausedAt, `the clock moved while paused from the menu: ${pausedAt} -> ${String(s.state?.t_sim)}`);
  await choose("pause");
  await waitFor(page, (s) => s.teleop?.paused === false && (s.state?.t_sim ?? 0) > pausedAt, { what: "the menu to resume the trial" });
  log("paused and resumed from the menu");

  await choose("stop_session");
  const end = await waitForEnd(page, 15000);
  const result = {
    session_id: end.ended.session_id,
    reason: end.ended.reason,
    actions: s.teleop?.actions ?? [],
    recenter_yaw: s.teleop?.recenter_yaw ?? null,
    snap_turned: turned,
  };
  console.log(`RESULT ${JSON.stringify(result)}`);
  check(end.ended.reason === "operator_stop", `the session ended ${end.ended.reason}, not operator_stop`);
});
