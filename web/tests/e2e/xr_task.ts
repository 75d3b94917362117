// A task other than box transfer, played in an emulated Meta Quest 3 (IWER) as far as one
// of its stages: the setup page offers the task, the session starts with it, the page
// enters immersive-vr, and the scripted operator drives with the thumbsticks and takes the
// first box on the belt with both controllers (grips held, palms in, triggers closed) until
// the HUD shows the stage asked for; then the session is stopped from the page. Prints
// "RESULT {json}" with the task stages the HUD showed, in order, for the pytest wrapper
// (tests/web/test_tasks_vr_browser.py).
//
//   npm run build:e2e && node build/e2e/tests/e2e/xr_task.js http://127.0.0.1:8000 palletize grasped   (in web/)

import { check, log, runScript, waitFor } from "./lib.js";
import { ScriptedOperator } from "./operator.js";
import { startSession } from "./flow.js";
import { deliver } from "./delivery.js";
import { HEADSET, XrDriver, applyAndObserve, restingHands } from "./xr_device.js";

const TICK_MS = 20;
const task = process.argv[3] ?? "palletize";
const goalStage = process.argv[4] ?? "grasped";

await runScript(`xr_${task}`, async ({ url, page, artifacts }) => {
  await startSession(page, url, { operatorId: `e2e-xr-${task}`, query: { emulate: "quest3" }, artifacts, task });
  check(await page.evaluate(() => window.__xrDevice !== undefined), "the emulated Quest 3 is not installed");
  await page.click("#enter-vr"); // a click is the user gesture WebXR needs
  await waitFor(page, (s) => s.teleop?.presenting === true && s.teleop.xr_frames > 5, { what: "the XR session" });
  await page.evaluate(applyAndObserve, { headset: HEADSET, hands: restingHands() });
  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the countdown to end" });

  const stages: string[] = [];
  let stopping = false;
  const operator = new ScriptedOperator();
  const device = new XrDriver();
  const run = await deliver(page, artifacts, operator, {
    prefix: `xr-${task}`,
    tickMs: TICK_MS,
    debugEveryMs: 1000,
    adaptLead: true,
    look: async () => {
      const seen = await page.evaluate(applyAndObserve, stopping ? null : device.command);
      const stage = seen.snap.hud?.stage;
      if (stage !== undefined && stage !== stages[stages.length - 1]) {
        stages.push(stage);
        log(`stage: ${stage} at t=${seen.snap.state?.t_sim.toFixed(2)} s`);
      }
      if (stage === goalStage && !stopping) {
        stopping = true;
        // out of VR, then the page's Stop and its confirmation (no reason given)
        await page.evaluate(() => document.querySelector<HTMLButtonElement>("#enter-vr")?.click());
        await waitFor(page, (s) => s.teleop?.presenting === false, { what: "the XR session to end" });
        await page.click("#stop-session");
        await page.click("#stop-confirm");
      }
      return seen;
    },
    act: (decision, obs, snap) => Promise.resolve(stopping ? 0 : device.act(decision, obs, snap)),
    debug: (decision) => `drive=${JSON.stringify(decision.drive)} grip=${decision.grip} trigger=${decision.trigger}`,
  });
  const result = {
    task,
    session_id: run.end.ended.session_id,
    outcome: run.trialEnd.outcome,
    stages,
    base_moved_m: Number(run.baseMovedM.toFixed(3)),
    xr_inputs_with_pose: device.inputsWithPose,
    max_grip: run.maxGrip,
  };
  console.log(`RESULT ${JSON.stringify(result)}`);
  check(stages.includes(goalStage), `the HUD never showed ${goalStage} (stages ${stages.join(" > ")})`);
});
