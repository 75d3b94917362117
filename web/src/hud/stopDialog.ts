// The confirmation asked before a session stops (the operator's Stop, the admin's Stop of a
// participant's session): what stopping does, an optional reason in the stopper's words
// (recorded with the stop and shown to the participant), and two buttons. Escape or
// "Keep going" cancels.

import { STOP_REASON_MAX } from "../app";
import { el } from "../util/dom";
import "./studyControl.css";

export interface StopQuestion {
  title: string;
  /** What stopping does, in a sentence or two. */
  explain: string;
  confirm: string;
}

/** Ask, in `container`; resolves with the reason given ("" for none), or null when the
 * person chose not to stop. Only one question is open at a time: a second call while
 * one is open resolves null at once. */
export function askToStop(container: HTMLElement, question: StopQuestion): Promise<string | null> {
  if (container.querySelector("#stop-dialog") !== null) return Promise.resolve(null);
  return new Promise((resolve) => {
    const dialog = el("div", { className: "stop-dialog", id: "stop-dialog", role: "dialog" });
    dialog.setAttribute("aria-modal", "true");
    const reason = el("textarea", {
      id: "stop-reason",
      rows: 2,
      maxLength: STOP_REASON_MAX,
      placeholder: "Why? (optional; recorded with the stop)",
    });
    const confirm = el("button", { type: "button", id: "stop-confirm", className: "danger", textContent: question.confirm });
    const cancel = el("button", { type: "button", id: "stop-cancel", textContent: "Keep going" });
    dialog.append(
      el("h2", { textContent: question.title }),
      el("p", { textContent: question.explain }),
      el("label", { className: "stop-reason-label" }, "Reason", reason),
      el("div", { className: "actions" }, cancel, confirm),
    );
    const close = (answer: string | null): void => {
      dialog.remove();
      document.removeEventListener("keydown", onKey, true);
      resolve(answer);
    };
    const onKey = (event: KeyboardEvent): void => {
      if (event.key === "Escape") {
        event.stopPropagation();
        close(null);
      }
    };
    confirm.addEventListener("click", () => close(reason.value.trim()));
    cancel.addEventListener("click", () => close(null));
    document.addEventListener("keydown", onKey, true);
    container.append(dialog);
    reason.focus();
  });
}
