// What the client knows from the server's messages, without the link: the scene, the
// newest state and HUD, the running session and what happened in it. `apply` takes one
// ServerMessage and says what changed; it is exhaustive over the generated union, so a
// new message type does not compile until it is handled here.

import type {
  FieldProblem,
  Hud,
  Queued,
  Scene,
  ServerMessage,
  SessionEnded,
  SessionStarted,
  State,
  TaskEvent,
  TrialEnded,
  Welcome,
} from "../protocol";

export type AppEvent =
  | { kind: "link" }
  | { kind: "scene" }
  | { kind: "session" }
  | { kind: "task_event"; event: TaskEvent }
  | { kind: "config_rejected"; problems: readonly FieldProblem[] }
  | { kind: "queued"; message: string }
  | { kind: "server_error"; code: string; message: string; problem: FieldProblem | null };

export const EVENT_HISTORY = 200;
export const ERROR_HISTORY = 50;

export class ClientModel {
  welcome: Welcome | null = null;
  scene: Scene | null = null;
  /** The newest State (older ones are never drawn). */
  state: State | null = null;
  hud: Hud | null = null;
  session: SessionStarted | null = null;
  /** The running session's id (from Welcome after a reconnect, or SessionStarted). */
  sessionId: string | null = null;
  ended: SessionEnded | null = null;
  /** The latest trial_ended event of this session (for the end-of-trial screen). */
  lastTrialEnd: TrialEnded | null = null;
  readonly events: TaskEvent[] = [];
  /** Whether the grippers hold a box (the latest grasp_changed of this trial). */
  holding = false;
  errors: { code: string; message: string }[] = [];
  /** Whether the running trial stands paused (its latest paused/resumed event). */
  paused = false;
  /** The operator's start waits in line for headroom: the server's latest word (null:
   * not waiting). */
  queued: Queued | null = null;
  /** Count of State messages received and of those dropped as stale. */
  readonly stats = { states: 0, stale: 0 };

  get sessionActive(): boolean {
    return this.sessionId !== null && this.ended === null;
  }

  /** Take in one message from the server; returns what changed, for the pages (null when
   * nothing a page listens for did). */
  apply(message: ServerMessage): AppEvent | null {
    switch (message.type) {
      case "welcome":
        this.welcome = message;
        this.sessionId = message.session_id;
        this.state = null; // a new link numbers its states afresh
        if (message.session_id !== null) this.ended = null;
        return { kind: "session" };
      case "scene":
        this.scene = message;
        return { kind: "scene" };
      case "state":
        this.stats.states += 1;
        if (this.state !== null && message.seq <= this.state.seq && message.seq !== 0) {
          this.stats.stale += 1;
          return null;
        }
        this.state = message;
        if (message.hud !== null) this.hud = message.hud;
        return null;
      case "session_started":
        this.queued = null;
        this.paused = false;
        this.session = message;
        this.sessionId = message.session_id;
        this.ended = null;
        this.lastTrialEnd = null;
        this.events.length = 0;
        this.state = null;
        return { kind: "session" };
      case "session_ended":
        this.paused = false;
        this.ended = message;
        this.sessionId = null;
        return { kind: "session" };
      case "event":
        this.applyEvent(message);
        return { kind: "task_event", event: message };
      case "config_rejected":
        return { kind: "config_rejected", problems: message.problems };
      case "error":
        if (message.message.startsWith("start_session")) this.queued = null; // the start was refused
        this.errors.push({ code: message.code, message: message.message });
        if (this.errors.length > ERROR_HISTORY) this.errors.shift();
        return { kind: "server_error", code: message.code, message: message.message, problem: message.problem };
      case "queued":
        this.queued = message;
        return { kind: "queued", message: message.message };
      case "pong":
        return null;
      default:
        return unhandled(message);
    }
  }

  private applyEvent(event: TaskEvent): void {
    this.events.push(event);
    if (this.events.length > EVENT_HISTORY) this.events.shift();
    switch (event.kind) {
      case "trial_ended":
        this.lastTrialEnd = event;
        break;
      case "countdown_started":
        this.holding = false;
        break;
      case "trial_started":
        // The end-of-trial screen stays up through the next trial's countdown.
        this.lastTrialEnd = null;
        this.holding = false;
        this.paused = false;
        break;
      case "paused":
        this.paused = true;
        break;
      case "resumed":
        this.paused = false;
        break;
      case "grasp_changed":
        this.holding = event.engaged;
        break;
      case "box_released":
      case "box_delivered":
      case "level_changed":
      case "trial_timed_out":
      case "trial_interrupted":
      case "operator_action":
      case "stop_requested":
      case "client_frames": // recorded only; the server does not send it
      case "take_over": // who drives: each State's HUD says (taken_over)
      case "hand_back":
        break;
      default:
        unhandled(event);
    }
  }
}

/** A compile-time check that a switch covers its union (and a loud failure if a newer
 * server sends what this client does not know). */
function unhandled(value: never): null {
  console.warn("workcell: unknown message from the server", value);
  return null;
}
