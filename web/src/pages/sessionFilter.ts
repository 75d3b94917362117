// The Sessions page's filters (participant, condition, study step, outcome or inclusion),
// kept in the page's address (`#/sessions?participant=p01&condition=physical`) so a link
// opens the page filtered, and the shown trials as a CSV download. Pure: no DOM.

import type { SessionSummary, TrialSummary } from "../protocol";

/** Which trials a researcher looks at by their outcome or inclusion; "" is every trial. */
export const TRIAL_KINDS = ["", "included", "not_included", "success", "timeout", "interrupted", "running"] as const;
export type TrialKind = (typeof TRIAL_KINDS)[number];

export const TRIAL_KIND_LABELS: Record<TrialKind, string> = {
  "": "every trial",
  included: "included",
  not_included: "not included",
  success: "success",
  timeout: "timeout",
  interrupted: "interrupted",
  running: "running",
};

/** The filter; "" in a field means any. `step` is a study step's number as text. */
export interface SessionFilter {
  participant: string;
  condition: string;
  step: string;
  trials: TrialKind;
}

export const NO_FILTER: SessionFilter = { participant: "", condition: "", step: "", trials: "" };

/** What the filter's condition and step menus say for a session outside any. */
export const NONE = "(none)";

const QUERY_KEYS: Record<keyof SessionFilter, string> = {
  participant: "participant",
  condition: "condition",
  step: "step",
  trials: "trials",
};

function isTrialKind(text: string): text is TrialKind {
  return (TRIAL_KINDS as readonly string[]).includes(text);
}

/** The filter a `#/sessions?...` address names (unknown keys and trial kinds are ignored). */
export function filterFromHash(hash: string): SessionFilter {
  const query = hash.includes("?") ? hash.slice(hash.indexOf("?") + 1) : "";
  const params = new URLSearchParams(query);
  const trials = params.get(QUERY_KEYS.trials) ?? "";
  return {
    participant: params.get(QUERY_KEYS.participant) ?? "",
    condition: params.get(QUERY_KEYS.condition) ?? "",
    step: params.get(QUERY_KEYS.step) ?? "",
    trials: isTrialKind(trials) ? trials : "",
  };
}

/** `#/sessions?participant=p01`: the address of the page with this filter. */
export function hashOf(filter: SessionFilter): string {
  const params = new URLSearchParams();
  for (const key of Object.keys(QUERY_KEYS) as (keyof SessionFilter)[]) {
    if (filter[key] !== "") params.set(QUERY_KEYS[key], filter[key]);
  }
  const query = params.toString();
  return query === "" ? "#/sessions" : `#/sessions?${query}`;
}

/** The values each menu offers: every participant, condition and study step recorded. */
export function filterChoices(sessions: readonly SessionSummary[]): {
  participants: string[];
  conditions: string[];
  steps: string[];
} {
  const participants = new Set<string>();
  const conditions = new Set<string>();
  const steps = new Set<number>();
  let outside = false;
  let unstepped = false;
  for (const s of sessions) {
    participants.add(s.operator_id);
    if (s.condition === null) outside = true;
    else conditions.add(s.condition);
    if (s.study_step === null) unstepped = true;
    else steps.add(s.study_step);
  }
  return {
    participants: [...participants].sort(),
    conditions: [...[...conditions].sort(), ...(outside ? [NONE] : [])],
    steps: [...[...steps].sort((a, b) => a - b).map(String), ...(unstepped ? [NONE] : [])],
  };
}

function matchesTrial(trial: TrialSummary, kind: TrialKind): boolean {
  switch (kind) {
    case "":
      return true;
    case "included":
      return trial.included === true;
    case "not_included":
      return trial.included === false;
    case "running":
      return trial.outcome === null;
    case "success":
    case "timeout":
    case "interrupted":
      return trial.outcome === kind;
  }
}

function matchesSession(session: SessionSummary, filter: SessionFilter): boolean {
  const condition = session.condition ?? NONE;
  const step = session.study_step === null ? NONE : String(session.study_step);
  return (
    (filter.participant === "" || session.operator_id === filter.participant) &&
    (filter.condition === "" || condition === filter.condition) &&
    (filter.step === "" || step === filter.step)
  );
}

/** The sessions the filter keeps, each with only the trials it keeps; with a trial kind
 * chosen, a session left with no trial is dropped. */
export function applyFilter(sessions: readonly SessionSummary[], filter: SessionFilter): SessionSummary[] {
  const kept: SessionSummary[] = [];
  for (const session of sessions) {
    if (!matchesSession(session, filter)) continue;
    const trials = session.trials.filter((trial) => matchesTrial(trial, filter.trials));
    if (filter.trials !== "" && trials.length === 0) continue;
    kept.push({ ...session, trials });
  }
  return kept;
}

/** The columns of the page's CSV download: the study tags, then the trial as the page shows it. */
export const TRIALS_CSV_COLUMNS = [
  "session_id",
  "operator_id",
  "condition",
  "study_step",
  "trial_id",
  "trial_index",
  "mode",
  "round",
  "level",
  "outcome",
  "interruption_reason",
  "boxes_delivered",
  "required_boxes",
  "elapsed_s",
  "score",
  "n_frames",
  "quality_flags",
  "included",
  "exclusion_reason",
] as const;

function cell(value: unknown): string {
  if (value === null || value === undefined) return "";
  const text = Array.isArray(value) ? value.join(";") : String(value);
  return /[",\n\r]/.test(text) ? `"${text.replaceAll('"', '""')}"` : text;
}

/** The shown trials as CSV (one row per trial, its session's study tags on each row). */
export function trialsCsv(sessions: readonly SessionSummary[]): string {
  const lines = [TRIALS_CSV_COLUMNS.join(",")];
  for (const s of sessions) {
    for (const t of s.trials) {
      const row: Record<(typeof TRIALS_CSV_COLUMNS)[number], unknown> = {
        session_id: s.session_id,
        operator_id: s.operator_id,
        condition: s.condition,
        study_step: s.study_step,
        trial_id: t.trial_id,
        trial_index: t.trial_index,
        mode: t.mode,
        round: t.round,
        level: t.level,
        outcome: t.outcome,
        interruption_reason: t.interruption_reason,
        boxes_delivered: t.boxes_delivered,
        required_boxes: t.required_boxes,
        elapsed_s: t.elapsed_s,
        score: t.score,
        n_frames: t.n_frames,
        quality_flags: t.quality_flags,
        included: t.included,
        exclusion_reason: t.exclusion_reason,
      };
      lines.push(TRIALS_CSV_COLUMNS.map((name) => cell(row[name])).join(","));
    }
  }
  return `${lines.join("\r\n")}\r\n`;
}
