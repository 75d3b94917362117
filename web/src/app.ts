// What the client knows, in one place: the link, the scene, the newest state, the running
// session and what happened in it. Pages read it and subscribe to changes; the server
// stays the authority and this is only its latest word.

import type { Act, Role } from "./protocol";
import { Connection } from "./net/connection";
import { ClientModel } from "./net/model";
import type { AppEvent } from "./net/model";
import { requestedRole } from "./util/env";

export type { AppEvent } from "./net/model";

type Listener = (event: AppEvent) => void;

/** The longest stop reason the server takes (workcell.task.events.STOP_NOTE_MAX). */
export const STOP_REASON_MAX = 300;

export class App extends ClientModel {
  readonly connection: Connection;
  private readonly listeners = new Set<Listener>();

  constructor(role: Role = requestedRole()) {
    super();
    this.connection = new Connection({
      role,
      onMessage: (message) => {
        const change = this.apply(message);
        if (change !== null) this.emit(change);
      },
      onStatus: () => this.emit({ kind: "link" }),
    });
  }

  get isOperator(): boolean {
    return this.connection.role === "operator";
  }

  start(): void {
    this.connection.connect();
  }

  subscribe(listener: Listener): () => void {
    this.listeners.add(listener);
    return () => this.listeners.delete(listener);
  }

  /** Start a session; `consent`: the operator accepted a study's consent text (a study
   * participant's settings come from their plan, not from `settings`). */
  startSession(settings: Record<string, unknown>, consent = false): boolean {
    this.ended = null;
    this.lastTrialEnd = null;
    this.queued = null;
    return this.connection.send({ type: "start_session", settings, consent });
  }

  /** Stop the running session; `reason`: the operator's words (recorded, may be empty). */
  stopSession(reason = ""): boolean {
    return this.connection.send({ type: "stop", reason: reason.trim().slice(0, STOP_REASON_MAX) });
  }

  /** Pause (true) or resume (false) the running trial: its clock and the physics stop. */
  pause(paused: boolean): boolean {
    return this.connection.send({ type: "pause", paused });
  }

  /** Whether an autonomous driver (expert, policy) drives this session, so the person may
   * take over. */
  get autonomous(): boolean {
    return this.hud !== null && this.hud.driver !== "person";
  }

  /** The person takes control from the session's driver, or hands it back (recorded with
   * `reason`); false when the session's driver is the person or nothing was sent. */
  toggleDriving(reason = ""): boolean {
    if (!this.autonomous || !this.sessionActive || !this.isOperator) return false;
    const type = this.hud?.taken_over === true ? "hand_back" : "take_over";
    return this.connection.send({ type, reason: reason.trim().slice(0, STOP_REASON_MAX) });
  }

  /** Take control (true) or hand it back (false), unless it is so already. */
  setDriving(person: boolean, reason = ""): boolean {
    if (!this.autonomous || (this.hud?.taken_over === true) === person) return false;
    return this.toggleDriving(reason);
  }

  /** An operator action besides driving (recorded by the server as an event). */
  act(action: Act["action"], source: Act["source"]): boolean {
    return this.connection.send({ type: "act", action, source });
  }

  private emit(event: AppEvent): void {
    for (const listener of this.listeners) listener(event);
  }
}
