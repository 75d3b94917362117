// Palletize on the desktop page with keyboard and mouse only, as far as its first stages:
// the setup page offers the task, a practice session starts with it, and the scripted
// operator (the one desktop_delivery.ts drives) walks the robot to the first box on the
// belt and takes it in both hands by keys (WASD/QE drive, G/H grips, Z palms in, F/J
// grippers, comma/period hands together/apart) and the mouse (the gripped hands). Once the
// HUD shows the box grasped the session is stopped. Prints "RESULT {json}" with the task
// stages the HUD showed, in order.
//
//   npm run build:e2e && node build/e2e/tests/e2e/palletize_desktop.js http://127.0.0.1:8000   (in web/)

import type { Keyboard } from "playwright-core";
import type { Pose } from "../../src/protocol";
import { check, log, runScript, sleep, waitFor } from "./lib.js";
import type { DebugSnapshot } from "./lib.js";
import { ScriptedOperator, controllerCorrections } from "./operator.js";
import type { Decision, Observation } from "./operator.js";
import { startSession } from "./flow.js";
import { deliver } from "./delivery.js";

const TASK = "palletize";
const GOAL_STAGE = "grasped";
const TICK_MS = 15;
const TAP_MS = 110;
const SETTLE_MS = 250;
const METRES_PER_PIXEL = 0.0015; // src/input/desktop.ts MOUSE_METRES_PER_PIXEL
const METRES_PER_WHEEL = 0.0004; // src/input/desktop.ts WHEEL_METRES_PER_UNIT
const PALM_IN_Z = Math.SQRT1_2;
const DRIVE_KEYS = ["w", "a", "s", "d", "q", "e"];

function observeJs(): { snap: DebugSnapshot; bodies: Record<string, Pose> } {
  const workcell = window.__workcell;
  if (workcell === undefined) throw new Error("no window.__workcell");
  return { snap: workcell.snapshot(), bodies: workcell.bodies() };
}

async function setKeys(keyboard: Keyboard, down: Set<string>, wanted: ReadonlySet<string>): Promise<void> {
  for (const key of [...down]) {
    if (!wanted.has(key)) {
      await keyboard.up(key);
      down.delete(key);
    }
  }
  for (const key of wanted) {
    if (!down.has(key)) {
      await keyboard.down(key);
      down.add(key);
    }
  }
}

await runScript("palletize_desktop", async ({ url, page, artifacts }) => {
  await startSession(page, url, { operatorId: "e2e-palletize", query: { quality: "low" }, artifacts, task: TASK });
  const canvas = page.locator("canvas.viewer-canvas");
  const view = await canvas.boundingBox();
  check(view !== null, "no 3D view on the teleop page");
  const centre = { x: view.x + view.width / 2, y: view.y + view.height / 2 };
  await page.mouse.click(centre.x, centre.y); // focus the view
  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the countdown to end" });

  const stages: string[] = [];
  let stopping = false;
  const down = new Set<string>();
  const operator = new ScriptedOperator({ onOff: true, lead: 0.25, tolerance: 0.03, slowDrive: true });
  let mouse: { x: number; y: number } | null = null;
  const act = async (decision: Decision, obs: Observation, snap: DebugSnapshot): Promise<number> => {
    const sent = snap.teleop?.last_input ?? null;
    const wanted = new Set<string>();
    const { forward, left, turn } = decision.drive;
    if (forward > 0.05) wanted.add("w");
    if (forward < -0.05) wanted.add("s");
    if (left > 0.05) wanted.add("a");
    if (left < -0.05) wanted.add("d");
    if (turn > 0.05) wanted.add("e");
    if (turn < -0.05) wanted.add("q");
    if (wanted.size > 0 && Math.max(Math.abs(forward), Math.abs(left), Math.abs(turn)) <= 0.5) wanted.add("Shift");
    if (decision.grip) wanted.add("g").add("h");
    if (decision.trigger) wanted.add("f").add("j");
    const following = obs.following[0] && obs.following[1];
    if (decision.grip && decision.palmsIn && following && sent !== null) {
      const zs = [sent.left.pose?.[6] ?? 0, -(sent.right.pose?.[6] ?? 0)];
      if (Math.min(...zs) < PALM_IN_Z - 0.01) wanted.add("z");
    }
    const [cl, cr] = controllerCorrections(obs, decision.targets, 0.8, 0.05);
    if (cl !== null && cr !== null && following) {
      const together = (cl[0] - cr[0]) / 2;
      if (together > 0.004) wanted.add("Comma");
      if (together < -0.004) wanted.add("Period");
      const common = [0, 1, 2].map((k) => ((cl[k] ?? 0) + (cr[k] ?? 0)) / 2);
      if (mouse === null) {
        mouse = { ...centre };
        await page.mouse.move(mouse.x, mouse.y);
        await page.mouse.down();
      }
      const nx = mouse.x + Math.round((common[0] ?? 0) / METRES_PER_PIXEL);
      const ny = mouse.y + Math.round((common[2] ?? 0) / METRES_PER_PIXEL);
      if (nx < view.x + 5 || nx > view.x + view.width - 5 || ny < view.y + 5 || ny > view.y + view.height - 5) {
        await page.mouse.up();
        mouse = { ...centre };
        await page.mouse.move(mouse.x, mouse.y);
        await page.mouse.down();
      } else {
        mouse = { x: nx, y: ny };
        await page.mouse.move(mouse.x, mouse.y);
      }
      const wheel = Math.round(-(common[1] ?? 0) / METRES_PER_WHEEL);
      if (Math.abs(wheel) >= 5) await page.mouse.wheel(0, wheel);
    } else if (mouse !== null && !decision.grip) {
      await page.mouse.up();
      mouse = null;
    }
    await setKeys(page.keyboard, down, wanted);
    if (decision.drive.fine && DRIVE_KEYS.some((k) => wanted.has(k))) {
      await sleep(TAP_MS);
      for (const k of DRIVE_KEYS) wanted.delete(k);
      await setKeys(page.keyboard, down, wanted);
      const settle = Math.max(SETTLE_MS, operator.lead * 1000);
      await sleep(settle);
      return TAP_MS + settle;
    }
    return 0;
  };
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
        await setKeys(page.keyboard, down, new Set());
        if (mouse !== null) await page.mouse.up();
        mouse = null;
        await page.click("#stop-session");
        await page.click("#stop-confirm"); // the confirmation, with no reason given
      }
      return seen;
    },
    act: async (decision, obs, snap) => (stopping ? 0 : act(decision, obs, snap)),
    debug: (decision) => `drive=${JSON.stringify(decision.drive)} keys=${[...down]}`,
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
