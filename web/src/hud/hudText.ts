// The HUD's content, one function for both the desktop overlay and the XR panel.

import type { Hud } from "../protocol";

export interface HudLine {
  label: string;
  value: string;
  /** A line that should stand out (countdown, little time left). */
  alert?: boolean;
}

export function clock(seconds: number): string {
  const s = Math.max(0, Math.ceil(seconds));
  const m = Math.floor(s / 60);
  return `${m}:${String(s % 60).padStart(2, "0")}`;
}

export function hudLines(hud: Hud): HudLine[] {
  const lines: HudLine[] = [{ label: "Mode", value: hud.mode }];
  if (hud.mode === "challenge") {
    const rounds = hud.rounds !== null ? `/${hud.rounds}` : "";
    lines.push({ label: "Round", value: `${hud.round ?? "-"}${rounds}` });
    lines.push({ label: "Level", value: String(hud.level ?? "-") });
  } else {
    lines.push({ label: "Trial", value: String(hud.trial_index + 1) });
  }
  lines.push({ label: "Boxes", value: `${hud.boxes_delivered}/${hud.required_boxes}` });
  if (hud.phase === "countdown") {
    lines.push({ label: "Starts in", value: String(Math.ceil(hud.countdown_s)), alert: true });
  }
  lines.push({
    label: "Time left",
    value: clock(hud.remaining_s),
    alert: hud.phase === "running" && hud.remaining_s <= 10,
  });
  lines.push({ label: "Score", value: String(hud.score) });
  return lines;
}

/** The headline of the end-of-trial screen from a trial_ended event's fields. */
export function trialEndSummary(fields: { readonly [key: string]: unknown }): HudLine[] {
  const num = (key: string): number | null => {
    const value = fields[key];
    return typeof value === "number" ? value : null;
  };
  const lines: HudLine[] = [];
  const outcome = typeof fields["outcome"] === "string" ? fields["outcome"] : "ended";
  lines.push({ label: "Outcome", value: outcome, alert: outcome !== "success" });
  const reason = fields["interruption_reason"];
  if (typeof reason === "string") lines.push({ label: "Reason", value: reason });
  const boxes = num("boxes_delivered");
  if (boxes !== null) lines.push({ label: "Boxes delivered", value: String(boxes) });
  const elapsed = num("elapsed_s");
  if (elapsed !== null) lines.push({ label: "Time", value: `${elapsed.toFixed(1)} s` });
  const score = num("score");
  if (score !== null) lines.push({ label: "Score", value: String(score) });
  return lines;
}
