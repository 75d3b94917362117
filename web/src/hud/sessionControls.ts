// The operator's controls of a running session besides driving: pause and resume (button,
// key P, the in-VR menu's "Pause") and stop, confirmed and with an optional reason (the
// toolbar's dialog; in VR, "Stop session" chosen twice). They also keep the participant's
// study status, for the end screen's next step of their plan.

import type { App } from "../app";
import { fetchParticipant } from "../net/api";
import type { ParticipantStatus } from "../protocol";
import { el } from "../util/dom";
import { renderEndScreen } from "./endScreen";
import { askToStop } from "./stopDialog";

export class SessionControls {
  readonly pauseButton = el("button", { id: "pause-session", textContent: "Pause" });
  readonly stopButton = el("button", { id: "stop-session", textContent: "Stop session" });
  /** The participant's study status (null: not a study participant; undefined: asking). */
  study: ParticipantStatus | null | undefined = undefined;
  /** "Stop session" was chosen once in the in-VR menu: choosing it again stops. */
  stopArmed = false;
  private disposed = false;

  constructor(
    private readonly app: App,
    private readonly viewport: HTMLElement,
    private readonly overlay: HTMLElement,
  ) {
    this.pauseButton.title = "pause the trial: its clock and the robot stand still (key P)";
    this.pauseButton.addEventListener("click", () => this.togglePause());
    this.stopButton.addEventListener("click", () => this.confirmStop());
  }

  /** Ask for the participant's study status again (its progress moved on). */
  loadStudy(): void {
    this.study = undefined;
    fetchParticipant()
      .catch(() => null)
      .then((status) => {
        if (this.disposed) return;
        this.study = status;
        this.renderOverlay();
      });
  }

  renderOverlay(): void {
    renderEndScreen(this.overlay, this.app, {
      status: this.study,
      onNextStep: () => this.app.startSession({}, false),
      onResume: () => this.app.pause(false),
    });
  }

  /** The buttons as the session and the operator's role allow. */
  sync(): void {
    const idle = !this.app.sessionActive || !this.app.isOperator;
    this.stopButton.disabled = idle;
    this.pauseButton.disabled = idle;
    this.pauseButton.textContent = this.app.paused ? "Resume" : "Pause";
  }

  togglePause(): void {
    if (this.app.sessionActive && this.app.isOperator) this.app.pause(!this.app.paused);
  }

  /** Ask the operator to confirm (and say why), then stop. */
  confirmStop(): void {
    const inStudy = this.study !== null && this.study !== undefined;
    const explain = inStudy
      ? "The trial under way ends, marked interrupted. The trials already done are kept: your next start goes on from this trial."
      : "The trial under way ends, marked interrupted; the trials already done are kept.";
    void askToStop(this.viewport, { title: "Stop the session?", explain, confirm: "Stop session" }).then((reason) => {
      if (reason !== null) this.app.stopSession(reason);
    });
  }

  /** The in-VR menu's "Stop session": the first choice arms it (true: keep the menu open
   * on "Confirm stop"), the second stops. */
  chooseStopInVr(): boolean {
    if (this.stopArmed) {
      this.stopArmed = false;
      this.app.stopSession("");
      return false;
    }
    this.stopArmed = true;
    return true;
  }

  dispose(): void {
    this.disposed = true;
  }
}
