// A task's first stage on the desktop page, keyboard only: pick the task on the setup page,
// wait for the box the plan names, drive the robot up to it (Q/E turn, W/A/S/D drive,
// Shift slow), hold both grips (G/H), bring the hands together (comma) and lower them (V)
// onto the box until the HUD's stage says a gripper touched it. sort_desktop.ts and
// shelve_desktop.ts are its plans.

import path from "node:path";
import type { Keyboard, Page } from "playwright-core";
import type { Pose } from "../../src/protocol";
import { check, checkDrawn, log, sleep, waitFor } from "./lib.js";
import type { DebugSnapshot } from "./lib.js";
import { yawOf } from "./observation.js";
import type { Base } from "./observation.js";
import { startSession } from "./flow.js";
import { HANDS_TOGETHER, TOLERANCE, YAW_TOLERANCE, approachLeft, handsApart } from "./approach.js";

const TICK_MS = 40;
const TAP_MS = 110; // a key tap near the goal...
const SETTLE_MS = 300; // ...then let the base stop before looking again
const LONGEST_TAP_MS = 600; // a tap that did not move the base is held twice as long next time, up to this
const LOWER_FOR_S = 20; // trial time the hands may go down without a touch before the script gives up
const TIME_LIMIT_S = "300"; // the trial's: a loaded machine draws few frames a second
const STALL_MS = 60000;
const DRIVE_KEYS = ["w", "a", "s", "d", "q", "e"];

export interface TouchPlan {
  task: string;
  operatorId: string;
  /** The box to drive to, once it can be reached (null: wait and look again); asked at
   * each look until it answers. */
  boxToReach: (bodies: Record<string, Pose>, t: number) => Pose | null;
  /** Where the base stands for that box (x, y, yaw). */
  standFor: (box: Pose) => Base;
}

export interface Touched {
  /** The page's last state, the HUD at `touched`. */
  last: DebugSnapshot;
  /** The trial's time when the HUD first showed a stage past `none` (s). */
  tSim: number;
  baseMovedM: number;
  keysUsed: string[];
}

interface Look {
  snap: DebugSnapshot;
  bodies: Record<string, Pose>;
}

function lookJs(): Look {
  const workcell = window.__workcell;
  if (workcell === undefined) throw new Error("no window.__workcell");
  return { snap: workcell.snapshot(), bodies: workcell.bodies() };
}

/** Hold exactly the keys in `wanted`, pressing and releasing only what changed. */
async function hold(keyboard: Keyboard, down: Set<string>, wanted: ReadonlySet<string>, used: Set<string>): Promise<void> {
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
      used.add(key);
    }
  }
}

/** Start a practice session of `plan.task` and drive to the HUD's `touched` by keys. */
export async function touchByKeys(page: Page, url: string, artifacts: string, plan: TouchPlan): Promise<Touched> {
  const { task } = plan;
  await startSession(page, url, {
    operatorId: plan.operatorId,
    query: { quality: "low" },
    artifacts,
    task,
    settings: { "task.time_limit_s": TIME_LIMIT_S },
  });
  const canvas = page.locator("canvas.viewer-canvas");
  const area = await canvas.boundingBox();
  check(area !== null, "no 3D view on the teleop page");
  await page.mouse.click(area.x + area.width / 2, area.y + area.height / 2); // focus the view
  const running = await waitFor(page, (s) => s.hud?.phase === "running", { what: "the countdown to end" });
  check(running.hud?.task === task, `the HUD names the task ${running.hud?.task}`);
  check(running.hud?.stage === "none", `the trial starts at stage ${running.hud?.stage}`);
  await checkDrawn(page, path.join(artifacts, `${task}-start.png`));

  const keyboard = page.keyboard;
  const down = new Set<string>();
  const used = new Set<string>();
  let step: "wait" | "drive" | "grip" | "together" | "lower" = "wait";
  let last = running;
  let lastT = -1;
  let lastProgress = Date.now();
  const started = last.state?.t_sim ?? 0;
  let startBase: [number, number] | null = null;
  let movedM = 0;
  let loggedAt = 0;
  let goal: Base | null = null;
  let loweringSince: number | null = null;
  let tapMs = TAP_MS;
  let tappedFrom: Base | null = null; // where the base was when the last tap began
  while (last.hud?.stage === "none") {
    const { snap, bodies } = await page.evaluate(lookJs);
    last = snap;
    const t = snap.state?.t_sim ?? 0;
    if (t !== lastT) {
      lastT = t;
      lastProgress = Date.now();
    }
    check(Date.now() - lastProgress < STALL_MS, "the simulation stopped advancing");
    check(snap.hud?.phase === "running", `the trial ended (${snap.hud?.phase}) before the box was touched`);
    const basePose = bodies["base"];
    check(basePose !== undefined, "the page shows no base");
    const base: Base = [basePose[0], basePose[1], yawOf(basePose)];
    startBase ??= [base[0], base[1]];
    movedM = Math.max(movedM, Math.hypot(base[0] - startBase[0], base[1] - startBase[1]));
    if (tappedFrom !== null) {
      // A tap the base did not follow (a page drawing few frames, a base leaning on the
      // table) is held longer next time; one it followed, as short again.
      const moved = Math.hypot(base[0] - tappedFrom[0], base[1] - tappedFrom[1]) > 0.005 || Math.abs(base[2] - tappedFrom[2]) > 0.005;
      tapMs = moved ? TAP_MS : Math.min(2 * tapMs, LONGEST_TAP_MS);
      tappedFrom = null;
    }
    const wanted = new Set<string>();
    let tap = false;
    if (step === "wait") {
      const box = plan.boxToReach(bodies, t);
      if (box !== null) {
        goal = plan.standFor(box);
        log(`the box can be reached after ${(t - started).toFixed(1)} s: ${box.slice(0, 3).map((v) => v.toFixed(2)).join(", ")}`);
        step = "drive";
      }
    }
    if (step === "drive" && goal !== null) {
      const { yawError, ex, ey, done } = approachLeft(base, goal);
      if (Math.abs(yawError) > YAW_TOLERANCE) {
        wanted.add(yawError > 0 ? "q" : "e"); // Q turns left (counter-clockwise)
        tap = Math.abs(yawError) < 0.25;
        if (Math.abs(yawError) < 0.8) wanted.add("Shift");
      } else if (!done) {
        if (Math.abs(ex) > TOLERANCE) wanted.add(ex > 0 ? "w" : "s");
        if (Math.abs(ey) > TOLERANCE) wanted.add(ey > 0 ? "a" : "d");
        tap = Math.max(Math.abs(ex), Math.abs(ey)) < 0.3;
      } else {
        log(`at the box after ${(t - started).toFixed(1)} s: base ${base.map((v) => v.toFixed(2)).join(", ")}`);
        step = "grip";
      }
      if (tap || Math.hypot(ex, ey) < 0.6) wanted.add("Shift");
    }
    if (step === "grip") {
      wanted.add("g").add("h");
      if (snap.state?.following[0] === true && snap.state.following[1]) step = "together";
    }
    if (step === "together") {
      wanted.add("g").add("h");
      const [left, right] = snap.state?.tcp_targets ?? [null, null];
      check(left !== null && right !== null, "no arm targets in the state");
      if (handsApart(left, right) > HANDS_TOGETHER) wanted.add("Comma");
      else step = "lower";
    }
    if (step === "lower") {
      wanted.add("g").add("h").add("v"); // down until a pad meets the box's top
      loweringSince ??= t;
      const [left, right] = snap.state?.tcp_targets ?? [null, null];
      check(
        t - loweringSince < LOWER_FOR_S,
        `the hands went down for ${LOWER_FOR_S} s without touching the box (the base went to ${JSON.stringify(goal)}; ` +
          `arm targets ${JSON.stringify(left?.slice(0, 3))} / ${JSON.stringify(right?.slice(0, 3))})`,
      );
    }
    if (Date.now() - loggedAt > 2000) {
      loggedAt = Date.now();
      log(`t=${t.toFixed(2)} ${step} base ${base.map((v) => v.toFixed(2)).join(", ")} keys ${[...wanted].join("")}`);
    }
    await hold(keyboard, down, wanted, used);
    if (tap) {
      tappedFrom = base;
      await sleep(tapMs);
      for (const key of DRIVE_KEYS) wanted.delete(key);
      await hold(keyboard, down, wanted, used);
      await sleep(SETTLE_MS);
    } else {
      await sleep(TICK_MS);
    }
    last = (await page.evaluate(lookJs)).snap;
  }
  await hold(keyboard, down, new Set(), used);
  check(last.hud?.stage === "touched", `the stage after the touch is ${last.hud?.stage}`);
  await checkDrawn(page, path.join(artifacts, `${task}-touched.png`));
  const tSim = last.state?.t_sim ?? 0;
  log(`touched after ${(tSim - started).toFixed(1)} s of the trial`);
  return { last, tSim, baseMovedM: movedM, keysUsed: [...used].sort() };
}

/** The RESULT fields both keyboard scripts print. */
export function touchedResult(run: Touched): Record<string, unknown> {
  const { last } = run;
  return {
    session_id: last.session_id,
    stage: last.hud?.stage ?? null,
    task: last.hud?.task ?? null,
    t_sim: last.state?.t_sim ?? null,
    base_moved_m: Number(run.baseMovedM.toFixed(3)),
    keys_used: run.keysUsed,
    source: last.teleop?.last_input?.source ?? null,
  };
}
