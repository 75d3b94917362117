// The screens over the 3D view between trials: the end of a trial (with what comes
// next), the end of the session or campaign, and "no session running".

import type { App } from "../app";
import { el } from "../util/dom";
import { sessionEndSummary, trialEndSummary } from "./hudText";
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

/** Fill `overlay` for the app's current state (hidden while a trial runs). */
export function renderEndScreen(overlay: HTMLElement, app: App): void {
  overlay.replaceChildren();
  const ended = app.ended;
  const trialEnd = app.lastTrialEnd;
  if (ended !== null) {
    overlay.className = "overlay campaign-end";
    overlay.append(
      el("h2", { textContent: ended.trials > 1 ? "Campaign complete" : "Session complete" }),
      linesToDom(sessionEndSummary(ended), "summary"),
    );
    if (trialEnd !== null) {
      overlay.append(
        el("h3", { textContent: "Last trial" }),
        linesToDom(trialEndSummary(trialEnd), "summary"),
      );
    }
    const actions = el("div", { className: "actions" });
    actions.append(
      el("a", { href: "#/", className: "button primary", textContent: "New session" }),
      el("a", { href: "#/sessions", className: "button", textContent: "Sessions and replay" }),
    );
    overlay.append(actions);
  } else if (trialEnd !== null) {
    overlay.className = "overlay trial-end";
    const outcome = trialEnd.outcome;
    overlay.append(
      el("h2", { textContent: outcome === "success" ? "Delivered!" : `Trial over: ${outcome}` }),
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
