// A study participant's start page (the page opened with their invite): the study's
// instructions, its consent text (accepted once, before the first session), how far they
// are and what they run next. The server takes the settings from their plan.

import type { App } from "../app";
import type { ParticipantStatus, PlannedStep } from "../protocol";
import { fetchParticipant } from "../net/api";
import { el } from "../util/dom";

function describeStep(step: PlannedStep): string {
  const what =
    step.mode === "practice"
      ? "one practice trial"
      : step.mode === "collection"
        ? `${step.trials} trials`
        : "a challenge (rounds of levels)";
  return `condition ${step.condition}: ${what}`;
}

export function mountStudyStart(root: HTMLElement, app: App): () => void {
  const page = el("section", { className: "page study-page" });
  page.append(el("p", { textContent: "Loading your study…" }));
  root.append(page);
  let disposed = false;
  let starting = false;
  let problem: HTMLElement | null = null;
  let startButton: HTMLButtonElement | null = null;

  const render = (status: ParticipantStatus): void => {
    page.replaceChildren();
    page.append(
      el("h1", { textContent: `Study ${status.study}` }),
      el("p", {
        className: "study-who",
        textContent: `You are participant ${status.participant}: ${status.done} of ${status.total} sessions done.`,
      }),
      el("progress", { className: "study-progress", value: status.done, max: status.total }),
    );
    if (status.instructions !== "") {
      page.append(
        el("h2", { textContent: "Instructions" }),
        el("div", { className: "study-instructions", textContent: status.instructions }),
      );
    }
    const next = status.next;
    if (next === null) {
      page.append(
        el("p", { className: "study-finished", textContent: "You have run every session of this study. Thank you!" }),
      );
      return;
    }
    let consent: HTMLInputElement | null = null;
    if (status.consent !== "" && !status.consented) {
      consent = el("input", { type: "checkbox", className: "study-consent-box" });
      page.append(
        el("h2", { textContent: "Consent" }),
        el("div", { className: "study-consent", textContent: status.consent }),
        el("label", { className: "study-consent-accept" }, consent, " I have read this and I agree to take part"),
      );
    }
    page.append(
      el("p", {
        className: "study-next",
        textContent: `Next: session ${next.position} of ${status.total}, ${describeStep(next)}.`,
      }),
    );
    const button = el("button", { type: "button", className: "primary start", textContent: "Start" });
    problem = el("p", { className: "problem general", role: "alert" });
    startButton = button;
    const box = consent;
    const sync = (): void => {
      button.disabled = starting || (box !== null && !box.checked);
    };
    box?.addEventListener("change", sync);
    sync();
    button.addEventListener("click", () => {
      if (problem !== null) problem.textContent = "";
      if (!app.startSession({}, box?.checked ?? false)) {
        if (problem !== null) problem.textContent = "Not connected to the server; retrying…";
        return;
      }
      starting = true;
      button.textContent = "Starting…";
      sync();
    });
    page.append(el("div", { className: "actions" }, button, problem));
  };

  const load = (): void => {
    fetchParticipant()
      .then((status) => {
        if (disposed) return;
        if (status === null) page.replaceChildren(el("p", { textContent: "This link is not a study invite." }));
        else render(status);
      })
      .catch((error: unknown) => {
        page.replaceChildren(el("p", { className: "problem", textContent: `Could not load your study: ${String(error)}` }));
      });
  };

  const unsubscribe = app.subscribe((event) => {
    if (event.kind === "session" && starting && app.session !== null && app.sessionActive) {
      starting = false;
      window.location.hash = "#/teleop";
    } else if (event.kind === "server_error" && starting) {
      starting = false;
      if (problem !== null) problem.textContent = event.message;
      if (startButton !== null) {
        startButton.textContent = "Start";
        startButton.disabled = false;
      }
    } else if (event.kind === "session" && app.ended !== null) {
      load();
    }
  });

  load();
  return () => {
    disposed = true;
    unsubscribe();
    page.remove();
  };
}
