// The delivery loop both device scripts share: each tick, look at the page, let the
// scripted operator decide, let the device carry the decision out; then the end of the
// trial and the checks every delivery must pass. Only looking and acting differ by
// device (emulated Quest controllers, or keyboard and mouse).

import { writeFileSync } from "node:fs";
import path from "node:path";
import type { Page } from "playwright-core";
import type { Pose, TrialEnded } from "../../src/protocol";
import { check, log, sleep, summary, writeJson } from "./lib.js";
import type { DebugSnapshot } from "./lib.js";
import { observe } from "./operator.js";
import type { Base, Decision, Observation, ScriptedOperator } from "./operator.js";
import { waitForEnd } from "./flow.js";
import type { EndedSnapshot } from "./flow.js";

/** What the page shows in one look. */
export interface Seen {
  snap: DebugSnapshot;
  bodies: Record<string, Pose>;
}

export interface DeliveryOptions {
  /** Screenshot names start with it (`xr`, `desktop`). */
  prefix: string;
  tickMs: number;
  /** How often to keep `debug`'s line (written to operator-trace.log, printed as it goes
   * with E2E_DEBUG set, and its tail printed when the delivery fails). */
  debugEveryMs: number;
  /** Read the page (and apply what `act` prepared, if the device works that way). */
  look: () => Promise<Seen>;
  /** Carry one decision out; returns the milliseconds it waited on purpose (a key tap
   * and the settling after it), which are not latency. */
  act: (decision: Decision, obs: Observation, snap: DebugSnapshot) => Promise<number>;
  debug: (decision: Decision, obs: Observation, snap: DebugSnapshot) => string;
  /** Set the operator's `lead` to the latency measured as it goes (the time a look and
   * an action take, without the waits on purpose, plus the link's round trip), at least
   * its initial value: on a slow machine the page draws a few frames a second, and an
   * operator that does not anticipate that overshoots. */
  adaptLead?: boolean;
}

export interface Delivery {
  operator: ScriptedOperator;
  last: DebugSnapshot;
  baseMovedM: number;
  maxGrip: number;
  maxTrigger: number;
  end: EndedSnapshot;
  trialEnd: TrialEnded;
}

const PHASE_SHOTS = ["squeeze", "carry", "place"];
/** How long the page may show no new simulated time before the delivery gives up. The
 * trial's own time limit (simulated time) ends the loop otherwise, however slowly a busy
 * machine runs it: there is no wall-clock budget to miss. */
const STALL_MS = 60000;
/** How long the session may take to end once its trial has (a condition, not a speed). */
const END_TIMEOUT_MS = 60000;
/** Trace lines printed when a delivery fails. */
const TRACE_TAIL = 25;
/** The most latency the operator anticipates (s): beyond it, it waits rather than guesses. */
const MAX_LEAD_S = 1.5;

/** Run the operator until the trial ends (by success or by its own time limit), then wait
 * for the session's end; its trial_ended event must have arrived. Fails if the simulated
 * time stops advancing for STALL_MS. */
export async function deliver(page: Page, artifacts: string, operator: ScriptedOperator, options: DeliveryOptions): Promise<Delivery> {
  const { prefix, tickMs, debugEveryMs, look, act, debug, adaptLead = false } = options;
  const minimumLead = operator.lead;
  let latencyS: number | null = null;
  const trace: string[] = [];
  let startBase: Base | null = null;
  let baseMovedM = 0;
  let maxGrip = 0;
  let maxTrigger = 0;
  let lastPhase = "";
  let shots = 0;
  let debugAt: number | undefined;
  let last: DebugSnapshot | null = null;
  let simulated = -Infinity; // the newest t_sim the page showed...
  let advancedAt = performance.now(); // ...and when it first showed it
  let stalled = false;
  for (;;) {
    const lookStarted = performance.now();
    const { snap, bodies } = await look();
    last = snap;
    if (snap.ended !== null || snap.last_trial_end !== null) break;
    const t = snap.state?.t_sim;
    if (t !== undefined && t > simulated) {
      simulated = t;
      advancedAt = lookStarted;
    } else if (lookStarted - advancedAt > STALL_MS) {
      stalled = true;
      break;
    }
    const base = bodies["base"];
    if (base === undefined) {
      await sleep(tickMs);
      continue;
    }
    const obs = observe(snap, { ...bodies, base });
    startBase ??= obs.base;
    baseMovedM = Math.max(baseMovedM, Math.hypot(obs.base[0] - startBase[0], obs.base[1] - startBase[1]));
    const decision = operator.step(obs);
    if (operator.phase !== lastPhase) {
      lastPhase = operator.phase;
      log(`operator: ${lastPhase} at t=${obs.t.toFixed(2)} s (base ${obs.base.map((v) => v.toFixed(2)).join(", ")})`);
      if (PHASE_SHOTS.includes(lastPhase) && shots < PHASE_SHOTS.length) {
        shots += 1;
        await page.screenshot({ path: path.join(artifacts, `${prefix}-${lastPhase}.png`) });
      }
    }
    if (debugAt === undefined || performance.now() - debugAt > debugEveryMs) {
      debugAt = performance.now();
      const line = `[${(debugAt / 1000).toFixed(1)}s] ${operator.phase} lead=${operator.lead.toFixed(2)} t=${obs.t.toFixed(2)} base=${obs.base.map((v) => v.toFixed(3))} ${debug(decision, obs, snap)}`;
      trace.push(line);
      if (process.env["E2E_DEBUG"]) log(`debug ${line}`);
    }
    const waited = await act(decision, obs, snap);
    if (adaptLead) {
      const seconds = (performance.now() - lookStarted - waited) / 1000;
      latencyS = latencyS === null ? seconds : 0.8 * latencyS + 0.2 * seconds;
      operator.lead = Math.min(MAX_LEAD_S, Math.max(minimumLead, latencyS + (snap.link.rttMs ?? 0) / 1000));
    }
    const sent = snap.teleop?.last_input;
    maxGrip = Math.max(maxGrip, sent?.left.grip ?? 0);
    maxTrigger = Math.max(maxTrigger, sent?.left.trigger ?? 0);
    await sleep(tickMs);
  }
  writeJson(path.join(artifacts, "operator-log.json"), operator.log);
  writeFileSync(path.join(artifacts, "operator-trace.log"), trace.join("\n") + "\n");
  log(`operator phases: ${JSON.stringify(operator.log)}`);
  check(last !== null, "the page never showed its state");
  let end: EndedSnapshot;
  try {
    check(!stalled, `the simulated time stayed at ${simulated} s for ${STALL_MS / 1000} s; last page state: ${JSON.stringify(summary(last))}`);
    end = await waitForEnd(page, END_TIMEOUT_MS);
  } catch (error) {
    log(`the operator's last ${Math.min(TRACE_TAIL, trace.length)} trace lines (all in operator-trace.log):\n${trace.slice(-TRACE_TAIL).join("\n")}`);
    throw error;
  }
  const trialEnd = end.last_trial_end;
  check(trialEnd !== null, "no trial_ended event arrived");
  log(`trial ended: ${JSON.stringify(trialEnd)}`);
  return { operator, last, baseMovedM, maxGrip, maxTrigger, end, trialEnd };
}

/** The RESULT fields every delivery reports. */
export function deliveryResult(run: Delivery): Record<string, unknown> {
  return {
    session_id: run.end.ended.session_id,
    outcome: run.trialEnd.outcome,
    boxes_delivered: run.trialEnd.boxes_delivered,
    score: run.trialEnd.score,
    base_moved_m: Number(run.baseMovedM.toFixed(3)),
    max_grip: run.maxGrip,
    max_trigger: run.maxTrigger,
    phases: run.operator.log,
    errors: run.end.errors,
  };
}

/** The checks every delivery must pass: the device drove the base, its grips and
 * triggers reached the server pressed, and the trial succeeded. */
export function checkDelivered(run: Delivery, device: string): void {
  check(run.baseMovedM > 0.2, `the ${device} did not drive the base (moved ${run.baseMovedM.toFixed(3)} m)`);
  check(run.maxGrip >= 0.99 && run.maxTrigger >= 0.99, "grips/triggers never reached the server as pressed");
  check(run.trialEnd.outcome === "success", `the trial ended ${run.trialEnd.outcome}, not success (phases ${JSON.stringify(run.operator.log)})`);
}
