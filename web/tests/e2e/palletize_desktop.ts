// Palletize on the desktop page with keyboard and mouse only, as far as its first stages:
// the setup page offers the task, a practice session starts with it, and the scripted
// operator (the one desktop_delivery.ts drives) walks the robot to the first box on the
// belt and takes it in both hands by keys (WASD/QE drive, G/H grips, Z palms in, F/J
// grippers, comma/period hands together/apart) and the mouse (the gripped hands). Once the
// HUD shows the box grasped the session is stopped. Prints "RESULT {json}" with the task
// stages the HUD showed, in order.
//
//   npm run build:e2e && node build/e2e/tests/e2e/palletize_desktop.js http://127.0.0.1:8000   (in web/)

import type { Pose } from "../../src/protocol";
import { check, log, runScript, waitFor } from "./lib.js";
import type { DebugSnapshot } from "./lib.js";
import { ScriptedOperator } from "./operator.js";
import { startSession } from "./flow.js";
import { deliver } from "./delivery.js";
import { DesktopHands, hideKeymap } from "./desktop_hands.js";

const TASK = "palletize";
const GOAL_STAGE = "grasped";
const TICK_MS = 15;
const TIME_LIMIT_S = "300"; // the trial's: a loaded machine draws few frames a second

function observeJs(): { snap: DebugSnapshot; bodies: Record<string, Pose> } {
  const workcell = window.__workcell;
  if (workcell === undefined) throw new Error("no window.__workcell");
  return { snap: workcell.snapshot(), bodies: workcell.bodies() };
}

await runScript("palletize_desktop", async ({ url, page, artifacts }) => {
  await startSession(page, url, {
    operatorId: "e2e-palletize",
    query: { quality: "low" },
    artifacts,
    task: TASK,
    settings: { "task.time_limit_s": TIME_LIMIT_S },
  });
  const canvas = page.locator("canvas.viewer-canvas");
  const view = await canvas.boundingBox();
  check(view !== null, "no 3D view on the teleop page");
  const centre = { x: view.x + view.width / 2, y: view.y + view.height / 2 };
  await page.mouse.click(centre.x, centre.y); // focus the view
  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the countdown to end" });
  await hideKeymap(page);

  const stages: string[] = [];
  let stopping = false;
  const operator = new ScriptedOperator({ onOff: true, lead: 0.25, tolerance: 0.03, slowDrive: true });
  const hands = new DesktopHands(page, view, operator);
  const run = await deliver(page, artifacts, operator, {
    prefix: "palletize",
    tickMs: TICK_MS,
    debugEveryMs: 500,
    adaptLead: true,
    look: async () => {
      const seen = await page.evaluate(observeJs);
      const stage = seen.snap.hud?.stage;
      if (stage !== undefined && stage !== stages[stages.length - 1]) {
        stages.push(stage);
        log(`stage: ${stage} at t=${seen.snap.state?.t_sim.toFixed(2)} s`);
      }
      if (stage === GOAL_STAGE && !stopping) {
        stopping = true;
        await hands.release();
        await page.click("#stop-session");
        await page.click("#stop-confirm"); // the confirmation, with no reason given
      }
      return seen;
    },
    act: async (decision, obs, snap) => (stopping ? 0 : hands.act(decision, obs, snap)),
    debug: (decision) => `drive=${JSON.stringify(decision.drive)} keys=${[...hands.keys.down]}`,
  });
  const result = {
    session_id: run.end.ended.session_id,
    outcome: run.trialEnd.outcome,
    stages,
    base_moved_m: Number(run.baseMovedM.toFixed(3)),
  };
  console.log(`RESULT ${JSON.stringify(result)}`);
  check(stages.includes(GOAL_STAGE), `the HUD never showed ${GOAL_STAGE} (stages ${stages.join(" > ")})`);
});
