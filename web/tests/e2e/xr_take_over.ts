// A person corrects the scripted expert from the emulated Meta Quest 3 (IWER; issue 35): a
// practice session with driver "expert" starts and the page enters immersive-vr; the person
// watches, squeezes both grips for a moment to take over (the HUD says they drive), raises
// the left controller with its grip held (the left arm follows), releases, hands back from
// the in-VR menu (X, the highlight down to "Hand back to expert", A), and the expert goes on
// and delivers the box. Prints "RESULT {json}".
//
// A second argument names another driver (policy:PATH): the session then runs 20 s and the
// policy drives on to the end after the hand-back, delivering or not.
//
//   npm run build:e2e && node build/e2e/tests/e2e/xr_take_over.js http://127.0.0.1:8000 [DRIVER]   (in web/)

import type { EmulatedDevice } from "../../src/xr/emulate";
import { check, log, runScript, sleep, waitFor } from "./lib.js";
import { startSession, waitForEnd } from "./flow.js";

type Side = "left" | "right";

interface Change {
  side: Side;
  button?: string;
  value?: number;
  y?: number;
  stickY?: number;
}

/** In the page: press a button or squeeze, move a controller up or down, tilt a stick. */
function device(change: Change): void {
  const quest: EmulatedDevice | undefined = window.__xrDevice;
  if (quest === undefined) throw new Error("the page has no emulated Quest");
  const controller = quest.controllers[change.side];
  if (controller === undefined) return;
  if (change.button !== undefined) controller.updateButtonValue(change.button, change.value ?? 0);
  if (change.y !== undefined) controller.position.set(change.side === "left" ? -0.2 : 0.2, change.y, -0.3);
  if (change.stickY !== undefined) controller.updateAxes("thumbstick", 0, change.stickY);
}

const MENU_ITEM = 5; // "take_over" in src/xr/vrMenu.ts MENU_ITEMS

const driver = process.argv[3] ?? "expert";
const expert = driver === "expert";
const settings: Record<string, string> = expert ? { driver } : { driver, "task.time_limit_s": "20" };

await runScript("xr_take_over", async ({ url, page }) => {
  await startSession(page, url, {
    operatorId: "e2e-xr-corrector",
    query: { emulate: "quest3", quality: "low" },
    settings,
  });
  await page.click("#enter-vr");
  await waitFor(page, (s) => s.teleop?.presenting === true && s.teleop.xr_frames > 5, { what: "the XR session" });
  for (const side of ["left", "right"] as const) await page.evaluate<void, Change>(device, { side, y: 1.0 });
  const watching = await waitFor(page, (s) => s.hud?.phase === "running" && (s.state?.t_sim ?? 0) > 2, {
    what: "the expert to drive for two seconds",
  });
  const named = watching.hud?.driver ?? "";
  check((expert ? named === "expert" : named.startsWith("policy:")) && watching.hud?.taken_over === false, `the HUD reads ${JSON.stringify(watching.hud)}`);

  // Both grips squeezed for a moment: the person takes over.
  for (const side of ["left", "right"] as const) await page.evaluate<void, Change>(device, { side, button: "squeeze", value: 1 });
  const took = await waitFor(page, (s) => s.hud?.taken_over === true, { what: "both grips held to take over" });
  log(`took over at t=${took.state?.t_sim.toFixed(2)} s`);
  await sleep(300);
  const before = (await waitFor(page, (s) => s.state !== null)).state?.tcp_targets[0][2] ?? 0;
  for (let k = 1; k <= 30; k += 1) {
    await page.evaluate<void, Change>(device, { side: "left", y: 1.0 + 0.004 * k });
    await sleep(40);
  }
  await sleep(400);
  const after = (await waitFor(page, (s) => s.state !== null)).state?.tcp_targets[0][2] ?? 0;
  log(`left target z ${before.toFixed(3)} -> ${after.toFixed(3)} m`);
  for (const side of ["left", "right"] as const) await page.evaluate<void, Change>(device, { side, button: "squeeze", value: 0 });

  // Hand back from the in-VR menu.
  const press = async (side: Side, button: string): Promise<void> => {
    await page.evaluate<void, Change>(device, { side, button, value: 1 });
    await sleep(150);
    await page.evaluate<void, Change>(device, { side, button, value: 0 });
    await sleep(150);
  };
  await press("left", "x-button");
  await waitFor(page, (s) => s.teleop?.menu.open === true, { what: "X to open the menu" });
  for (let i = 0; i < MENU_ITEM; i += 1) {
    await page.evaluate<void, Change>(device, { side: "right", stickY: 1 });
    await sleep(150);
    await page.evaluate<void, Change>(device, { side: "right", stickY: 0 });
    await sleep(150);
  }
  await waitFor(page, (s) => s.teleop?.menu.index === MENU_ITEM, { what: "the highlight on the take-over item" });
  await press("right", "a-button");
  await waitFor(page, (s) => s.hud?.taken_over === false, { what: "the menu to hand back" });
  log("handed back from the menu");

  const end = await waitForEnd(page, 200000);
  const result = {
    session_id: end.ended.session_id,
    successes: end.ended.successes,
    reason: end.ended.reason,
    driver: named,
    raised_m: Number((after - before).toFixed(3)),
  };
  console.log(`RESULT ${JSON.stringify(result)}`);
  if (expert) check(end.ended.successes === 1, `the expert did not deliver after the hand-back: ${JSON.stringify(end.ended)}`);
  else check(end.ended.reason === "completed", `the policy's session ended ${JSON.stringify(end.ended)}`);
});
