// A scripted "human" for the end-to-end tests: it looks at what the page draws (body
// poses, the arm targets, the HUD and task events from `window.__workcell`) and decides
// what an operator would do next, phase by phase: wait for a box at the end of the belt,
// drive up to it, take both grips, turn the palms inward, reach around the box, squeeze,
// close both grippers, lift, back off, carry it to the table, set it down, let go.
//
// It only decides; an actuator (emulated Quest controllers, or keyboard and mouse) turns
// its decisions into device input. Its output per step:
//   drive:   { forward, left, turn } desired base motion, each in [-1, 1] (stick units)
//   grip:    bool (both grips), trigger: bool (both grippers closed)
//   palmsIn: bool (palms turned to face each other)
//   targets: { l, r } desired TCP positions in the robot base frame (x fwd, y left, z up),
//            or null (hands free)
// Geometry: base frame = the robot's; WebXR local-floor x right, y up, -z forward, so a
// base-frame displacement (dx, dy, dz) is a controller displacement (-dy, dz, -dx).

import { add, norm, sub, toBase, wrap } from "./observation.js";
import type { Base, BoxSeen, Observation, Vec3 } from "./observation.js";

export type { Base, Observation, Vec3 } from "./observation.js";
export { observe } from "./observation.js";

export type Phase = "wait" | "approach" | "engage" | "pregrasp" | "squeeze" | "lift" | "carry" | "place" | "release" | "backoff";

export interface Targets {
  l: Vec3;
  r: Vec3;
}

export interface Drive {
  forward: number;
  left: number;
  turn: number;
  fine: boolean;
}

export interface Decision {
  drive: Drive;
  grip: boolean;
  trigger: boolean;
  palmsIn: boolean;
  targets: Targets | null;
}

const BOX_HALF = 0.15; // half the default box width across the belt (the grasp axis)
const BELT_TOP = 0.75;
const PICK_DISTANCE = 0.6;
const PREGRASP_GAP = 0.07;
const SQUEEZE_GAP = -0.006;
const LIFT: Vec3 = [-0.05, 0, 0.12];
const TABLE_TOP = 0.6;
const PLACE_DISTANCE = 0.8;
const ARM_REACH = 0.65;
const DEAD_ZONE = 0.15;
const SETTLE_AFTER_S = 10; // on the last leg to the table this long (sim time)...
const SETTLED_TOLERANCE = 0.06; // ...close enough is this close (m)
const REST_S = 0.4; // a box still for this long (trial time) rests

export interface OperatorOptions {
  slowDrive?: boolean;
  lead?: number;
  tolerance?: number;
  onOff?: boolean;
}

export class ScriptedOperator {
  readonly onOff: boolean;
  /** Set by a loop that measures its latency (see `deliver`'s `adaptLead`). */
  lead: number;
  readonly tolerance: number;
  readonly slowDrive: boolean;
  velocity: Vec3 = [0, 0, 0];
  phase: Phase = "wait";
  phaseStart: number | null = null;
  /** [t, phase] at each change of phase. */
  readonly log: [number, Phase][] = [];
  box: string | null = null;
  route: Base[] = [];
  targets: Targets | null = null;
  grip = false;
  trigger = false;
  palmsIn = false;
  drive: Drive = { forward: 0, left: 0, turn: 0, fine: false };
  lastBase: Base | null = null;
  baseSpeed = 0;
  lastT: number | null = null;
  private candidate: string | null = null;
  private candidatePos: Vec3 = [0, 0, 0];
  private candidateSince = 0; // trial time the candidate was first seen where it is
  private lifted: number | null = null;
  private lowering: number | null = null;
  private legStart: number | null = null;

  /** `lead` (s): drive on where the base will be after this long (the loop's latency),
   * as a person anticipates; `tolerance` (m): how close to the pick pose is close enough;
   * `onOff`: the drive is keys (full or slow, nothing between), not sticks. */
  constructor({ slowDrive = false, lead = 0, tolerance = 0.015, onOff = false }: OperatorOptions = {}) {
    this.onOff = onOff;
    this.lead = lead;
    this.tolerance = tolerance;
    this.slowDrive = slowDrive;
  }

  enter(phase: Phase, t: number): void {
    this.phase = phase;
    this.phaseStart = t;
    this.log.push([Number(t.toFixed(2)), phase]);
  }

  /** Stick deflection that moves the base toward `goal` = [x, y, yaw] (world). */
  driveTo(obs: Observation, goal: Base, tolerance = this.tolerance, vmax = 0.5): boolean {
    const [vx, vy, wz] = this.velocity;
    const base: Base = [obs.base[0] + vx * this.lead, obs.base[1] + vy * this.lead, obs.base[2] + wz * this.lead];
    const [ex, ey] = toBase(base, [goal[0], goal[1], 0]);
    const dist = Math.hypot(ex, ey);
    const eyaw = wrap(goal[2] - base[2]);
    const yawTolerance = 0.03 * Math.max(1, tolerance / 0.015);
    const arrived = Math.hypot(...toBase(obs.base, [goal[0], goal[1], 0]).slice(0, 2)) < tolerance &&
      Math.abs(wrap(goal[2] - obs.base[2])) < yawTolerance;
    if (this.onOff) {
      // Keys are on or off: one axis at a time near the goal, each with a dead band, as a
      // person tapping keys does (heading first, then along, then across).
      const near = dist < 0.3;
      const turnOn = Math.abs(eyaw) > yawTolerance / 2;
      // Full speed (no Shift) only far from the goal and when the caller allows it.
      const full = vmax >= 0.5;
      const turn = turnOn ? -Math.sign(eyaw) * (Math.abs(eyaw) > 0.4 && full ? 1 : 0.3) : 0;
      const speed = dist > 0.4 && full ? 1 : 0.3;
      let forward = 0;
      let left = 0;
      if (!(near && turnOn)) {
        if (Math.abs(ex) > tolerance / 2) forward = Math.sign(ex) * speed;
        else if (Math.abs(ey) > tolerance / 2) left = Math.sign(ey) * speed;
        if (!near && Math.abs(ey) > tolerance / 2) left = Math.sign(ey) * speed;
      }
      // Close in, a person taps the keys instead of holding them: near the goal, or when
      // only a small turn is left.
      const onlyTurning = forward === 0 && left === 0;
      const fine = Math.abs(eyaw) < 0.2 && (dist < 0.15 || onlyTurning);
      this.drive = { forward, left, turn, fine };
      return arrived;
    }
    // A proportional controller through a delay oscillates once gain x delay nears pi/2:
    // with the loop's latency (lead) beyond 0.3 s the gains shrink in proportion, as a
    // person on a laggy link eases off.
    const gain = Math.min(1, 0.3 / Math.max(this.lead, 0.3));
    const v = dist < tolerance * 0.5 ? 0 : Math.min(vmax, 1.2 * gain * dist);
    const m = v > 0 ? DEAD_ZONE + (1 - DEAD_ZONE) * Math.min(1, v / 0.8) : 0;
    const w = Math.max(-1, Math.min(1, 2 * gain * eyaw));
    const turn = Math.abs(eyaw) < 0.01 ? 0 : -(DEAD_ZONE + (1 - DEAD_ZONE) * Math.min(1, Math.abs(w) / 1.2)) * Math.sign(w);
    this.drive = { forward: v > 0 ? (ex / dist) * m : 0, left: v > 0 ? (ey / dist) * m : 0, turn, fine: false };
    return arrived;
  }

  /** The base neither drives nor turns (as far as the last looks tell). */
  standingStill(): boolean {
    return this.baseSpeed < 0.03 && Math.abs(this.velocity[2]) < 0.05;
  }

  stop(): void {
    this.drive = { forward: 0, left: 0, turn: 0, fine: false };
  }

  private chosenBox(obs: Observation): BoxSeen {
    const box = obs.boxes.find((b) => b.name === this.box);
    if (box === undefined) throw new Error(`the chosen box ${this.box} is not in the scene`);
    return box;
  }

  palms(obs: Observation, gap: number, lift = 0): Targets {
    const c = toBase(obs.base, this.chosenBox(obs).pos);
    c[2] += lift;
    return { l: [c[0], c[1] + BOX_HALF + gap, c[2]], r: [c[0], c[1] - BOX_HALF - gap, c[2]] };
  }

  handsAt(obs: Observation, tolerance: number): boolean {
    const targets = this.targets;
    if (targets === null) return false;
    return (
      norm(sub(toBase(obs.base, obs.tcp[0]), targets.l)) < tolerance &&
      norm(sub(toBase(obs.base, obs.tcp[1]), targets.r)) < tolerance
    );
  }

  step(obs: Observation): Decision {
    if (this.lastBase !== null && this.lastT !== null && obs.t > this.lastT) {
      const dt = obs.t - this.lastT;
      const now: Vec3 = [
        (obs.base[0] - this.lastBase[0]) / dt,
        (obs.base[1] - this.lastBase[1]) / dt,
        wrap(obs.base[2] - this.lastBase[2]) / dt,
      ];
      const k = Math.min(1, dt / 0.15); // low-pass over ~0.15 s
      this.velocity = [0, 1, 2].map((i) => this.velocity[i]! + k * (now[i]! - this.velocity[i]!)) as Vec3;
      this.baseSpeed = Math.hypot(this.velocity[0], this.velocity[1]);
    }
    this.lastBase = obs.base;
    this.lastT = obs.t;
    if (this.phaseStart === null) this.phaseStart = obs.t;
    const t = obs.t;
    const elapsed = t - this.phaseStart;
    switch (this.phase) {
      case "wait": {
        this.grip = false;
        this.trigger = false;
        const resting = obs.boxes.filter(
          (b) => Math.abs(b.pos[2] - (BELT_TOP + BOX_HALF)) < 0.03 && b.pos[0] > -0.5 && b.pos[0] < 0.2,
        );
        this.driveTo(obs, [1.0, 0, Math.PI]);
        if (resting.length > 0 && obs.phase === "running") {
          const candidate = resting.sort((a, b) => b.pos[0] - a.pos[0])[0]!;
          // At rest: within 3 mm of where it was first seen for REST_S of trial time (two
          // looks a loaded page answers from the same state would agree on a moving box).
          const still = this.candidate === candidate.name && norm(sub(candidate.pos, this.candidatePos)) < 0.003;
          if (!still) {
            this.candidate = candidate.name;
            this.candidatePos = candidate.pos;
            this.candidateSince = t;
          } else if (t - this.candidateSince >= REST_S) {
            this.box = candidate.name;
            this.enter("approach", t);
          }
        }
        break;
      }
      case "approach": {
        const box = this.chosenBox(obs);
        const heading = Math.PI + wrap(box.yaw);
        const goal: Base = [box.pos[0] - PICK_DISTANCE * Math.cos(heading), box.pos[1] - PICK_DISTANCE * Math.sin(heading), heading];
        if (this.driveTo(obs, goal, this.tolerance, this.slowDrive ? 0.3 : 0.6) && this.standingStill()) {
          this.stop();
          this.enter("engage", t);
        }
        break;
      }
      case "engage":
        this.stop();
        this.grip = true;
        this.palmsIn = false;
        if (obs.following[0] && obs.following[1]) {
          this.targets = this.palms(obs, PREGRASP_GAP);
          this.palmsIn = true;
          this.enter("pregrasp", t);
        }
        break;
      case "pregrasp":
        this.targets = this.palms(obs, PREGRASP_GAP);
        if ((this.handsAt(obs, 0.02) && elapsed > 0.5) || elapsed > 8) this.enter("squeeze", t);
        break;
      case "squeeze":
        this.targets = this.palms(obs, SQUEEZE_GAP);
        if (this.handsAt(obs, 0.03) || elapsed > 3) this.trigger = true;
        if (obs.holding) this.enter("lift", t);
        else if (elapsed > 8) {
          this.trigger = false;
          this.enter("pregrasp", t);
        }
        break;
      case "lift":
        if (this.lifted !== this.phaseStart && this.targets !== null) {
          this.lifted = this.phaseStart;
          this.targets = { l: add(this.targets.l, LIFT), r: add(this.targets.r, LIFT) };
        }
        if ((this.handsAt(obs, 0.03) && elapsed > 0.5) || elapsed > 3) {
          const [bx, by, yaw] = obs.base;
          const retreat: Base = [bx - 0.5 * Math.cos(yaw), by - 0.5 * Math.sin(yaw), yaw];
          const [zx, zy] = obs.zone;
          const dx = zx - retreat[0];
          const dy = zy - retreat[1];
          let h = Math.abs(dx) > Math.abs(dy) ? (dx > 0 ? 0 : Math.PI) : dy > 0 ? Math.PI / 2 : -Math.PI / 2;
          h = yaw + wrap(h - yaw);
          this.route = [retreat, [zx - PLACE_DISTANCE * Math.cos(h), zy - PLACE_DISTANCE * Math.sin(h), h]];
          this.enter("carry", t);
        }
        break;
      case "carry": {
        const goal = this.route[0];
        if (goal === undefined) break;
        const last = this.route.length === 1;
        this.legStart ??= t;
        // The last leg stops at the table; a person who keeps overshooting it (a laggy
        // link) settles for a little farther off after a while: the zone is 0.7 m wide and
        // the hands place the box where it belongs.
        const settle = t - this.legStart > SETTLE_AFTER_S ? SETTLED_TOLERANCE : 0;
        const tolerance = last ? Math.max(0.02, this.tolerance, settle) : 0.1;
        const arrived = this.driveTo(obs, goal, tolerance, this.slowDrive ? 0.35 : 0.6);
        if (arrived && (!last || this.standingStill())) {
          this.legStart = null;
          this.route.shift();
          if (this.route.length === 0) {
            this.stop();
            this.enter("place", t);
          }
        }
        break;
      }
      case "place": {
        // Hold the box where the hands have it and move the hands so that the box goes
        // first above its spot on the table, then down onto it.
        this.stop();
        const goal = toBase(obs.base, [obs.zone[0], obs.zone[1], TABLE_TOP + BOX_HALF + 0.012]);
        goal[0] = Math.min(goal[0], ARM_REACH);
        const held = toBase(obs.base, this.chosenBox(obs).pos);
        const lowering = this.lowering === this.phaseStart;
        const aim = lowering ? goal : add(goal, [0, 0, 0.06]);
        this.targets = {
          l: add(aim, sub(toBase(obs.base, obs.tcp[0]), held)),
          r: add(aim, sub(toBase(obs.base, obs.tcp[1]), held)),
        };
        const off = norm(sub(aim, held));
        if (!lowering && off < 0.03) this.lowering = this.phaseStart;
        if ((lowering && off < 0.02) || elapsed > 8) this.enter("release", t);
        break;
      }
      case "release":
        this.trigger = false;
        if (elapsed > 0.4) this.targets = this.palms(obs, 0.08, 0.02);
        if (elapsed > 1.5) {
          this.grip = false;
          this.targets = null;
          const [bx, by, yaw] = obs.base;
          this.route = [[bx - 0.4 * Math.cos(yaw), by - 0.4 * Math.sin(yaw), yaw]];
          this.enter("backoff", t);
        }
        break;
      case "backoff": {
        const goal = this.route[0];
        if (goal !== undefined && this.driveTo(obs, goal, 0.05)) this.route = [];
        if (this.route.length === 0) this.stop();
        break;
      }
    }
    return {
      drive: this.drive,
      grip: this.grip,
      trigger: this.trigger,
      palmsIn: this.palmsIn,
      targets: this.targets,
    };
  }
}

/** Per-hand controller corrections (local-floor) that bring the observed arm targets to
 * the desired ones; null for a hand whose arm does not follow yet. */
export function controllerCorrections(
  obs: Observation,
  targets: Targets | null,
  gain = 0.7,
  maxStep = 0.03,
): [Vec3 | null, Vec3 | null] {
  if (targets === null) return [null, null];
  const correction = (i: 0 | 1): Vec3 | null => {
    const observed = obs.targets[i];
    if (observed === null || !obs.following[i]) return null;
    const err = sub(i === 0 ? targets.l : targets.r, toBase(obs.base, observed));
    const [x, y, z] = err.map((v) => Math.max(-maxStep, Math.min(maxStep, v * gain))) as Vec3;
    return [-y, z, -x];
  };
  return [correction(0), correction(1)];
}
