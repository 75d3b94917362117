// The screens over the 3D view between trials: the end of a trial (with what comes
// next), the end of the session or campaign (in a study: the plan's next step), a paused
// trial, and "no session running".

import type { App } from "../app";
import type { ParticipantStatus, PlannedStep } from "../protocol";
import { el } from "../util/dom";
import { sessionEndSummary, sessionEndTitle, trialEndSummary } from "./hudText";
import type { HudLine } from "./hudText";

export function linesToDom(lines: readonly HudLine[], className: string): HTMLElement {
  const list = el("dl", { className });
  for (const line of lines) {
    const dt = el("dt", { textContent: line.label });
    const dd = el("dd", { textContent: line.value });
    if (line.alert === true) dd.classList.add("alert");
    list.append(dt, dd);
  }
  return list;
}

/** What comes after the trial that just ended (from the level_changed event, if any). */
function nextTrialText(app: App): string {
  const ended = app.lastTrialEnd;
  const after = ended === null ? [] : app.events.slice(app.events.lastIndexOf(ended) + 1);
  const change = after.find((e) => e.kind === "level_changed");
  if (change === undefined) return "The next trial starts by itself.";
  const where = `round ${change.round}, level ${change.level}`;
  return change.repeat ? `Time ran out: ${where} again.` : `Next: ${where}.`;
}

/** What the end screen offers in a study, and the page's hands for its buttons. */
export interface EndScreenStudy {
  /** The participant's status since the session ended: undefined while not known, null on
   * a page that is not a study participant's. */
  status?: ParticipantStatus | null;
  /** Start the plan's next session (or the rest of a stopped one). */
  onNextStep?: () => void;
  /** Resume the paused trial. */
  onResume?: () => void;
}

/** The plan's next step in words: which session, its condition, and where a stopped one
 * resumes. */
export function describeNextStep(next: PlannedStep, total: number): string {
  const what =
    next.mode === "practice"
      ? "one practice trial"
      : next.mode === "collection"
        ? `${next.trials} trials`
        : "a challenge (rounds of levels)";
  const resumed =
    next.trials_done > 0 ? `; ${next.trials_done} of its trials are done, it goes on with trial ${next.trials_done + 1}` : "";
  return `Next: session ${next.position} of ${total}, condition ${next.condition}: ${what}${resumed}.`;
}

function studyActions(status: ParticipantStatus, onNextStep: (() => void) | undefined): HTMLElement[] {
  const next = status.next;
  if (next === null) {
    return [el("p", { className: "study-next-step", textContent: "You have run every session of this study. Thank you!" })];
  }
  const button = el("button", {
    type: "button",
    id: "next-step",
    className: "button primary",
    textContent: next.trials_done > 0 ? "Resume this session" : "Start the next session",
  });
  button.addEventListener("click", () => {
    button.disabled = true;
    onNextStep?.();
  });
  return [
    el("p", { className: "study-next-step", textContent: describeNextStep(next, status.total) }),
    el("div", { className: "actions" }, button),
  ];
}

/** Fill `overlay` for the app's current state (hidden while a trial runs). */
export function renderEndScreen(overlay: HTMLElement, app: App, study: EndScreenStudy = {}): void {
  overlay.replaceChildren();
  const ended = app.ended;
  const trialEnd = app.lastTrialEnd;
  if (ended !== null) {
    overlay.className = "overlay campaign-end";
    overlay.append(
      el("h2", { textContent: sessionEndTitle(ended) }),
      linesToDom(sessionEndSummary(ended), "summary"),
    );
    if (trialEnd !== null) {
      overlay.append(
        el("h3", { textContent: "Last trial" }),
        linesToDom(trialEndSummary(trialEnd), "summary"),
      );
    }
    const status = study.status;
    if (status !== undefined && status !== null) {
      overlay.append(...studyActions(status, study.onNextStep));
    } else if (status === null) {
      const actions = el("div", { className: "actions" });
      actions.append(
        el("a", { href: "#/", className: "button primary", textContent: "New session" }),
        el("a", { href: "#/sessions", className: "button", textContent: "Sessions and replay" }),
      );
      overlay.append(actions);
    }
  } else if (app.sessionActive && app.paused) {
    overlay.className = "overlay paused";
    const resume = el("button", { type: "button", id: "resume-session", className: "button primary", textContent: "Resume" });
    resume.addEventListener("click", () => study.onResume?.());
    overlay.append(
      el("h2", { textContent: "Paused" }),
      el("p", { textContent: "The trial's clock and the robot stand still; the pause is not counted in its time." }),
      el("div", { className: "actions" }, resume),
    );
  } else if (trialEnd !== null) {
    overlay.className = "overlay trial-end";
    const outcome = trialEnd.outcome;
    overlay.append(
      el("h2", { textContent: outcome === "success" ? "Done!" : `Trial over: ${outcome}` }),
      linesToDom(trialEndSummary(trialEnd), "summary"),
      el("p", { textContent: nextTrialText(app) }),
    );
  } else if (!app.sessionActive) {
    overlay.className = "overlay idle";
    overlay.append(
      el("h2", { textContent: "No session running" }),
      el("a", { href: "#/", className: "button primary", textContent: "Set up a session" }),
    );
  } else {
    overlay.className = "overlay hidden";
  }
}
