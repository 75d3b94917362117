// End to end on the desktop page with keyboard and mouse only: set up a practice session,
// then the same scripted operator as in VR delivers the box, pressing keys the way a
// person would (WASD/QE drive, G/H hold the grips, Z turns the palms in, F/J close the
// grippers, comma/period bring the hands together or apart) and dragging the mouse / turning
// the wheel to move the gripped hands. Prints "RESULT {json}" for the pytest wrapper.
//
//   npm run build:e2e && node build/e2e/tests/e2e/desktop_delivery.js http://127.0.0.1:8000   (in web/)

import path from "node:path";
import type { Pose } from "../../src/protocol";
import { PATIENCE_MS, check, checkDrawn, runScript, waitFor, waitForFrames } from "./lib.js";
import type { DebugSnapshot } from "./lib.js";
import { ScriptedOperator } from "./operator.js";
import type { Decision, Observation, Vec3 } from "./operator.js";
import { norm, sub, toBase } from "./observation.js";
import { startSession } from "./flow.js";
import { checkDelivered, deliver, deliveryResult } from "./delivery.js";
import { DesktopHands, hideKeymap } from "./desktop_hands.js";

const TICK_MS = 15;
const TIME_LIMIT_S = "300"; // the trial's: a loaded machine draws few frames a second

function observeJs(): { snap: DebugSnapshot; bodies: Record<string, Pose> } {
  const workcell = window.__workcell;
  if (workcell === undefined) throw new Error("no window.__workcell");
  return { snap: workcell.snapshot(), bodies: workcell.bodies() };
}

/** How far (cm) each arm target and each hand is from where the operator wants it. */
function handErrors(decision: Decision, obs: Observation): string {
  const wanted = decision.targets;
  if (wanted === null) return "";
  const cm = (p: Vec3 | null, goal: Vec3): string => (p === null ? "-" : (100 * norm(sub(toBase(obs.base, p), goal))).toFixed(1));
  return `target_cm=${cm(obs.targets[0], wanted.l)}/${cm(obs.targets[1], wanted.r)} hand_cm=${cm(obs.tcp[0], wanted.l)}/${cm(obs.tcp[1], wanted.r)}`;
}

await runScript("desktop_delivery", async ({ url, page, artifacts }) => {
  await startSession(page, url, {
    operatorId: "e2e-desktop",
    query: { quality: "low" },
    artifacts,
    settings: { "task.time_limit_s": TIME_LIMIT_S },
  });
  const canvas = page.locator("canvas.viewer-canvas");
  const box = await canvas.boundingBox();
  check(box !== null, "no 3D view on the teleop page");
  const centre = { x: box.x + box.width / 2, y: box.y + box.height / 2 };
  await page.mouse.click(centre.x, centre.y); // focus the view

  // The key map is on screen.
  const keymap = (await page.textContent("#keymap")) ?? "";
  check(keymap.includes("W A S D") && keymap.includes("G / H"), "the key map is not shown");
  await waitForFrames(page);
  await checkDrawn(page, path.join(artifacts, "desktop-view.png"));

  // C toggles the view; both views are drawn.
  await page.keyboard.press("c");
  await waitFor(page, (s) => s.teleop?.view === "first", { what: "C to switch to first person" });
  await waitForFrames(page);
  await checkDrawn(page, path.join(artifacts, "desktop-first-person.png"));
  await page.keyboard.press("c");
  await waitFor(page, (s) => s.teleop?.view === "third", { what: "C to switch back" });

  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the countdown to end" });
  await checkDrawn(page, path.join(artifacts, "hud-running.png"), page.locator("#hud"));
  await hideKeymap(page);

  const operator = new ScriptedOperator({ onOff: true, lead: 0.25, tolerance: 0.03, slowDrive: true });
  const hands = new DesktopHands(page, box, operator);
  const keys = hands.keys;
  const run = await deliver(page, artifacts, operator, {
    prefix: "desktop",
    tickMs: TICK_MS,
    debugEveryMs: 500,
    adaptLead: true,
    look: () => page.evaluate(observeJs),
    act: (decision, obs, snap) => hands.act(decision, obs, snap),
    debug: (decision, obs, snap) => {
      const sent = snap.teleop?.last_input;
      const drive = JSON.stringify(decision.drive, (_k, v: unknown) => (typeof v === "number" ? Number(v.toFixed(2)) : v));
      return `drive=${drive} keys=${[...keys.down]} stick=${JSON.stringify(sent?.left.stick)}/${JSON.stringify(sent?.right.stick)} ${handErrors(decision, obs)} ${hands.lastCorrection}`;
    },
  });
  await hands.release();
  await page.waitForSelector("#end-screen.campaign-end", { timeout: PATIENCE_MS });
  await checkDrawn(page, path.join(artifacts, "end-screen.png"), page.locator("#end-screen"));
  await checkDrawn(page, path.join(artifacts, "view-end.png"));

  const result = {
    ...deliveryResult(run),
    keys_used: [...keys.pressed].sort(),
    source: run.last.teleop?.last_input?.source ?? null,
  };
  console.log(`RESULT ${JSON.stringify(result)}`);
  checkDelivered(run, "keyboard");
});
