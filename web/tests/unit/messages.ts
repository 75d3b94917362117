// Server messages for the unit tests, typed by the generated protocol (a field the
// protocol renames breaks these at compile time, as it would break the client).

import type { FieldProblem, GraspChanged, Hud, State, TrialEnded, TrialStarted } from "../../src/protocol";

export const hud = (over: Partial<Hud> = {}): Hud => ({
  phase: "running",
  mode: "collection",
  trial_index: 0,
  round: null,
  rounds: null,
  level: null,
  boxes_delivered: 0,
  required_boxes: 1,
  countdown_s: 0,
  remaining_s: 100,
  score: 0,
  task: "box_transfer",
  stage: "none",
  time_bonus: 100,
  driver: "person",
  taken_over: false,
  instruction: "Carry the box from the conveyor to the delivery table.",
  ...over,
});

const IDENTITY = [0, 0, 0, 1, 0, 0, 0] as const;

export const state = (seq: number, over: Partial<State> = {}): State => ({
  type: "state",
  seq,
  t_sim: seq / 30,
  poses: [],
  hud: hud(),
  input_seq: 0,
  tcp_targets: [IDENTITY, IDENTITY],
  following: [false, false],
  ...over,
});

export const grasp = (engaged: boolean): GraspChanged => ({
  type: "event",
  kind: "grasp_changed",
  trial_index: 0,
  t_sim: 1,
  box: 0,
  engaged,
});

export const trialStarted = (trial_index: number): TrialStarted => ({
  type: "event",
  kind: "trial_started",
  trial_index,
  t_sim: 0,
  mode: "collection",
  round: null,
  level: null,
  required_boxes: 1,
  time_limit_s: 120,
  trial_seed: 7,
  conditions: {},
});

export const trialEnded = (over: Partial<TrialEnded> = {}): TrialEnded => ({
  type: "event",
  kind: "trial_ended",
  trial_index: 0,
  t_sim: 12.5,
  outcome: "success",
  interruption_reason: null,
  elapsed_s: 12.5,
  boxes_delivered: 1,
  score: 190,
  ...over,
});

export const problem = (path: (string | number)[], value: unknown, allowed: string): FieldProblem => ({
  path,
  value,
  allowed,
  message: `${path.join(".")} = ${JSON.stringify(value)}: ${allowed}`,
});
