// What the client knows, in one place: the link, the scene, the newest state, the running
// session and what happened in it. Pages read it and subscribe to changes; the server
// stays the authority and this is only its latest word.

import type {
  FieldProblem,
  Hud,
  Role,
  Scene,
  ServerMessage,
  SessionEnded,
  SessionStarted,
  State,
  TaskEventMessage,
} from "./protocol";
import { Connection } from "./net/connection";
import { requestedRole } from "./util/env";

export type AppEvent =
  | { kind: "link" }
  | { kind: "scene" }
  | { kind: "session" }
  | { kind: "task_event"; event: TaskEventMessage }
  | { kind: "config_rejected"; problems: readonly FieldProblem[] }
  | { kind: "server_error"; code: string; message: string };

type Listener = (event: AppEvent) => void;

const EVENT_HISTORY = 200;

export class App {
  readonly connection: Connection;
  scene: Scene | null = null;
  /** The newest State (older ones are never drawn). */
  state: State | null = null;
  hud: Hud | null = null;
  session: SessionStarted | null = null;
  /** The running session's id (from Welcome after a reconnect, or SessionStarted). */
  sessionId: string | null = null;
  ended: SessionEnded | null = null;
  /** The latest trial_ended event of this session (for the end-of-trial screen). */
  lastTrialEnd: TaskEventMessage | null = null;
  readonly events: TaskEventMessage[] = [];
  holding = false;
  errors: { code: string; message: string }[] = [];
  private readonly listeners = new Set<Listener>();
  /** Count of State messages received and of those dropped as stale. */
  readonly stats = { states: 0, stale: 0 };

  constructor(role: Role = requestedRole()) {
    this.connection = new Connection({
      role,
      onMessage: (message) => this.receive(message),
      onStatus: () => this.emit({ kind: "link" }),
    });
  }

  get sessionActive(): boolean {
    return this.sessionId !== null && this.ended === null;
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

  startSession(settings: Record<string, unknown>): boolean {
    this.ended = null;
    this.lastTrialEnd = null;
    return this.connection.send({ type: "start_session", settings });
  }

  stopSession(): boolean {
    return this.connection.send({ type: "stop" });
  }

  private receive(message: ServerMessage): void {
    switch (message.type) {
      case "welcome":
        this.sessionId = message.session_id;
        this.state = null; // a new link numbers its states afresh
        if (message.session_id !== null) this.ended = null;
        this.emit({ kind: "session" });
        break;
      case "scene":
        this.scene = message;
        this.emit({ kind: "scene" });
        break;
      case "state":
        this.stats.states += 1;
        if (this.state !== null && message.seq <= this.state.seq && message.seq !== 0) {
          this.stats.stale += 1;
          break;
        }
        this.state = message;
        if (message.hud !== null) this.hud = message.hud;
        break;
      case "session_started":
        this.session = message;
        this.sessionId = message.session_id;
        this.ended = null;
        this.lastTrialEnd = null;
        this.events.length = 0;
        this.state = null;
        this.emit({ kind: "session" });
        break;
      case "session_ended":
        this.ended = message;
        this.sessionId = null;
        this.emit({ kind: "session" });
        break;
      case "event":
        this.events.push(message);
        if (this.events.length > EVENT_HISTORY) this.events.shift();
        if (message.kind === "trial_ended") this.lastTrialEnd = message;
        // The end-of-trial screen stays up through the next trial's countdown.
        if (message.kind === "trial_started") this.lastTrialEnd = null;
        if (message.kind === "countdown_started" || message.kind === "trial_started") {
          this.holding = false;
        }
        if (message.kind === "grasp_changed") this.holding = message.fields["engaged"] === true;
        this.emit({ kind: "task_event", event: message });
        break;
      case "config_rejected":
        this.emit({ kind: "config_rejected", problems: message.problems });
        break;
      case "error":
        this.errors.push({ code: message.code, message: message.message });
        if (this.errors.length > 50) this.errors.shift();
        this.emit({ kind: "server_error", code: message.code, message: message.message });
        break;
      case "pong":
        break;
    }
  }

  private emit(event: AppEvent): void {
    for (const listener of this.listeners) listener(event);
  }
}
