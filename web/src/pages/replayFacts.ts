// The replay page's list of its trial's facts, as label and value. Pure: no DOM.

import type { ReplayFacts } from "../protocol";

function num(value: number | null, digits = 0, unit = ""): string {
  return value === null ? "—" : `${value.toFixed(digits)}${unit}`;
}

/** The facts as label and value, in the order the page lists them. */
export function factLines(facts: ReplayFacts): [string, string][] {
  const level = facts.level !== null ? `round ${facts.round ?? "-"}, level ${facts.level}` : null;
  const reason = facts.interruption_reason !== null ? ` (${facts.interruption_reason})` : "";
  const included =
    facts.included === null ? "—" : facts.included ? "yes" : `no: ${facts.exclusion_reason ?? "not included"}`;
  const lines: [string, string][] = [
    ["participant", facts.operator_id],
    ["condition", facts.condition ?? "—"],
    ["study step", facts.study_step === null ? "—" : String(facts.study_step)],
    ["mode", facts.mode + (level !== null ? `, ${level}` : "")],
    ["outcome", (facts.outcome ?? "running") + reason],
    ["duration", `${num(facts.elapsed_s, 1, " s")} of ${facts.time_limit_s.toFixed(0)} s`],
    ["boxes", `${num(facts.boxes_delivered)}/${facts.required_boxes}`],
    ["score", num(facts.score)],
    ["included", included],
  ];
  return lines;
}
