// The HUD's content, one function for both the desktop overlay and the XR panel.

import type { Hud, SessionEnded, TrialEnded } from "../protocol";

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
  if (hud.driver !== "person") lines.push(drivingLine(hud));
  if (hud.mode === "challenge") {
    const rounds = hud.rounds !== null ? `/${hud.rounds}` : "";
    lines.push({ label: "Round", value: `${hud.round ?? "-"}${rounds}` });
    lines.push({ label: "Level", value: String(hud.level ?? "-") });
  } else {
    lines.push({ label: "Trial", value: String(hud.trial_index + 1) });
  }
  lines.push({ label: "Boxes", value: `${hud.boxes_delivered}/${hud.required_boxes}` });
  if (hud.phase === "running") lines.push({ label: "Stage", value: hud.stage.replaceAll("_", " ") });
  if (hud.phase === "countdown") {
    lines.push({ label: "Starts in", value: String(Math.ceil(hud.countdown_s)), alert: true });
  }
  lines.push({
    label: "Time left",
    value: clock(hud.remaining_s),
    alert: hud.phase === "running" && hud.remaining_s <= 10,
  });
  // The points earned so far: what the trial ends with unless it succeeds; a success
  // adds the seconds left, shown apart so the score never counts down.
  lines.push({ label: "Score", value: String(hud.score) });
  if (hud.phase === "running") lines.push({ label: "Time bonus", value: `+${hud.time_bonus} on success` });
  return lines;
}

/** Who drives a session an autonomous driver runs: the driver, or the person who took
 * over from it. */
export function drivingLine(hud: Hud): HudLine {
  return hud.taken_over
    ? { label: "Driving", value: `you (took over from ${hud.driver})`, alert: true }
    : { label: "Driving", value: `${hud.driver} (take over: T, both grips, menu)` };
}

type Interruption = NonNullable<TrialEnded["interruption_reason"]>;

const INTERRUPTED_BY: Record<Interruption, string> = {
  operator_stop: "stopped by you",
  admin_stop: "stopped by the study's administrator",
  operator_restart: "restarted",
  client_lost: "the connection was lost",
  application_quit: "the server was shut down",
  crash_recovered: "the server stopped unexpectedly",
  storage_error: "recording failed",
};

/** The headline of the end-of-trial screen from a trial_ended event. */
export function trialEndSummary(ended: TrialEnded): HudLine[] {
  const lines: HudLine[] = [{ label: "Outcome", value: ended.outcome, alert: ended.outcome !== "success" }];
  if (ended.interruption_reason !== null) lines.push({ label: "Reason", value: INTERRUPTED_BY[ended.interruption_reason] });
  lines.push({ label: "Boxes delivered", value: String(ended.boxes_delivered) });
  lines.push({ label: "Time", value: `${ended.elapsed_s.toFixed(1)} s` });
  lines.push({ label: "Score", value: String(ended.score) });
  return lines;
}

const ENDED_BY: Record<SessionEnded["reason"], string> = {
  completed: "Every trial of the session ran",
  operator_stop: "You stopped the session",
  admin_stop: "The study's administrator stopped the session",
  client_lost: "The connection to the server was lost for too long",
  application_quit: "The server was shut down",
  crash_recovered: "The server stopped unexpectedly; the trial was kept up to that moment",
  storage_error: "Recording failed",
  operator_restart: "The trial was restarted",
  error: "The session failed",
};

/** The end screen's title: whether the session ran to its end or was stopped. */
export function sessionEndTitle(ended: SessionEnded): string {
  if (ended.reason === "completed") return ended.trials > 1 ? "Campaign complete" : "Session complete";
  if (ended.reason === "operator_stop" || ended.reason === "admin_stop") return "Session stopped";
  return "Session ended";
}

/** How a session ended, in words: who stopped it and their reason, or what went wrong. */
export function endedInWords(ended: SessionEnded): string {
  const words = ENDED_BY[ended.reason];
  const why = ended.stop_note !== "" ? ended.stop_note : ended.detail;
  return why !== "" ? `${words}: ${why}` : words;
}

/** The end-of-session screen's summary from a session_ended message; an error or a failed
 * recording names what went wrong (a full disk, a dead store writer) and stands out. */
export function sessionEndSummary(ended: SessionEnded): HudLine[] {
  const failed = ended.reason === "error" || ended.reason === "storage_error";
  return [
    { label: "Trials", value: String(ended.trials) },
    { label: "Successes", value: String(ended.successes) },
    { label: "Total score", value: String(ended.total_score) },
    { label: "Ended", value: endedInWords(ended), alert: failed },
  ];
}
