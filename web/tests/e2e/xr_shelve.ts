// The shelve task in an emulated Meta Quest 3 (IWER), as far as its first stage: pick
// "shelve" on the setup page, enter immersive-vr, drive up to the box waiting on the table
// with the thumbsticks (left: ahead and sideways, right: turn), squeeze both grips, bring
// the controllers together and lower them until the HUD says a gripper touched the box;
// then leave VR and stop the session from the page. Prints "RESULT {json}" for the pytest
// wrapper (tests/web/test_tasks_vr_browser.py); the drive to the table is approach.ts's.
//
//   npm run build:e2e && node build/e2e/tests/e2e/xr_shelve.js http://127.0.0.1:8000   (in web/)

import { check, log, runScript, sleep, waitFor } from "./lib.js";
import { startSession } from "./flow.js";
import { yawOf } from "./observation.js";
import type { Vec3 } from "./observation.js";
import { HEADSET, NEUTRAL, REST, applyAndObserve, restingHands } from "./xr_device.js";
import type { DeviceCommand } from "./xr_device.js";
import { HANDS_TOGETHER, TOLERANCE, YAW_TOLERANCE, approachLeft, handsApart, standAtTable } from "./approach.js";

const TICK_MS = 40;
const STALL_MS = 60000;
const STEP_M = 0.004; // how far the controllers move per tick while bringing the hands in or down
const clamp = (v: number, limit: number): number => Math.max(-limit, Math.min(limit, v));
/** A stick deflection toward `error`: proportional, past the dead zone, at most `limit`. */
const deflect = (error: number, gain: number, limit = 0.8): number =>
  Math.abs(error) < 1e-9 ? 0 : Math.sign(error) * Math.max(0.25, Math.min(limit, Math.abs(error) * gain));

await runScript("xr_shelve", async ({ url, page, artifacts }) => {
  await startSession(page, url, { operatorId: "e2e-xr-shelve", query: { emulate: "quest3" }, artifacts, task: "shelve" });
  check(await page.evaluate(() => window.__xrDevice !== undefined), "the emulated Quest 3 is not installed");
  await page.click("#enter-vr"); // a click is the user gesture WebXR needs
  await waitFor(page, (s) => s.teleop?.presenting === true && s.teleop.xr_frames > 5, { what: "the XR session" });
  await page.evaluate(applyAndObserve, { headset: HEADSET, hands: restingHands() });
  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the countdown to end" });

  const stages: string[] = [];
  const left: Vec3 = [...REST.left];
  const right: Vec3 = [...REST.right];
  let step: "drive" | "grip" | "together" | "lower" = "drive";
  let command: DeviceCommand | null = null;
  let startBase: [number, number] | null = null;
  let movedM = 0;
  let lastT = -1;
  let lastProgress = Date.now();
  let maxGrip = 0;
  let inputsWithPose = 0;
  for (;;) {
    const { snap, bodies } = await page.evaluate(applyAndObserve, command);
    const stage = snap.hud?.stage;
    if (stage !== undefined && stage !== stages[stages.length - 1]) {
      stages.push(stage);
      log(`stage: ${stage} at t=${snap.state?.t_sim.toFixed(2)} s (${step})`);
    }
    if (stage !== undefined && stage !== "none") break;
    const t = snap.state?.t_sim ?? 0;
    if (t !== lastT) {
      lastT = t;
      lastProgress = Date.now();
    }
    check(Date.now() - lastProgress < STALL_MS, "the simulation stopped advancing");
    check(snap.hud?.phase === "running", `the trial ended (${snap.hud?.phase}) before the box was touched`);
    const basePose = bodies["base"];
    const boxPose = bodies["box_0"];
    check(basePose !== undefined && boxPose !== undefined, "the page shows no base or no box_0");
    const base: [number, number, number] = [basePose[0], basePose[1], yawOf(basePose)];
    startBase ??= [base[0], base[1]];
    movedM = Math.max(movedM, Math.hypot(base[0] - startBase[0], base[1] - startBase[1]));
    const sent = snap.teleop?.last_input;
    if (sent?.source === "xr" && sent.left.pose !== null && sent.right.pose !== null) inputsWithPose += 1;
    maxGrip = Math.max(maxGrip, sent?.left.grip ?? 0);
    let drive: [number, number, number] = [0, 0, 0]; // ahead, left, turn (counter-clockwise)
    if (step === "drive") {
      const { yawError, ex, ey, done } = approachLeft(base, standAtTable(boxPose));
      if (Math.abs(yawError) > YAW_TOLERANCE) drive = [0, 0, deflect(yawError, 2)];
      else if (!done) drive = [Math.abs(ex) > TOLERANCE ? deflect(ex, 1.5) : 0, Math.abs(ey) > TOLERANCE ? deflect(ey, 1.5) : 0, 0];
      else {
        log(`at the table after ${t.toFixed(1)} s: base ${base.map((v) => v.toFixed(2)).join(", ")}`);
        step = "grip";
      }
    } else if (step === "grip") {
      if (snap.state?.following[0] === true && snap.state.following[1]) step = "together";
    } else {
      const [l, r] = snap.state?.tcp_targets ?? [null, null];
      check(l !== null && r !== null, "no arm targets in the state");
      if (step === "together" && handsApart(l, r) > HANDS_TOGETHER) {
        left[0] += STEP_M;
        right[0] -= STEP_M;
      } else {
        step = "lower"; // down until a pad meets the box's top
        left[1] -= STEP_M;
        right[1] -= STEP_M;
      }
    }
    const grip = step === "drive" ? 0 : 1;
    command = {
      hands: {
        // xr-standard thumbstick: x right, y down; the right stick's x turns clockwise
        left: { pos: [...left], quat: NEUTRAL, grip, trigger: 0, stick: [clamp(-drive[1], 1), clamp(-drive[0], 1)] },
        right: { pos: [...right], quat: NEUTRAL, grip, trigger: 0, stick: [clamp(-drive[2], 1), 0] },
      },
    };
    await sleep(TICK_MS);
  }
  // Leave VR, then stop from the page (confirmed, no reason given).
  await page.evaluate(applyAndObserve, { hands: restingHands() });
  await page.evaluate(() => document.querySelector<HTMLButtonElement>("#enter-vr")?.click());
  await waitFor(page, (s) => s.teleop?.presenting === false, { what: "the XR session to end" });
  await page.click("#stop-session");
  await page.click("#stop-confirm");
  const ended = await waitFor(page, (s) => s.ended !== null, { what: "the session to end" });
  const result = {
    task: "shelve",
    session_id: ended.ended?.session_id ?? null,
    stages,
    base_moved_m: Number(movedM.toFixed(3)),
    xr_inputs_with_pose: inputsWithPose,
    max_grip: maxGrip,
  };
  console.log(`RESULT ${JSON.stringify(result)}`);
  check(stages.includes("touched"), `the HUD never showed touched (stages ${stages.join(" > ")})`);
});
