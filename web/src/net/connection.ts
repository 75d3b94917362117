// The WebSocket link to the server: Hello on every (re)connect, automatic reconnection
// with exponential backoff, and the resume token that takes back a session's control.

import { SUBPROTOCOL } from "../protocol";
import type { ClientMessage, Role, ServerMessage, Welcome } from "../protocol";
import { requestedSeat, serverUrl } from "../util/env";

export type LinkStatus = "connecting" | "open" | "reconnecting" | "refused";

export interface LinkInfo {
  status: LinkStatus;
  /** Why the server refused us (protocol mismatch, bad token), when `refused`. */
  reason: string | null;
  /** Reconnect attempts since the link was last open. */
  attempts: number;
  /** Round-trip time of the last ping, ms. */
  rttMs: number | null;
}

const RESUME_KEY = "workcell.resume_token";
const BACKOFF_START_MS = 250;
const BACKOFF_MAX_MS = 5000;
const PING_EVERY_MS = 2000;
/** No message at all for this long (the server streams state) means a dead link. */
const SILENCE_LIMIT_MS = 8000;
/** Close codes after which retrying cannot help. */
const REFUSED_CODES = new Set([1002, 1008, 4000, 4001, 4003, 4400, 4401, 4403]);

export interface ConnectionOptions {
  role: Role;
  onMessage: (message: ServerMessage) => void;
  onStatus: (info: LinkInfo) => void;
}

export class Connection {
  readonly info: LinkInfo = { status: "connecting", reason: null, attempts: 0, rttMs: null };
  private socket: WebSocket | null = null;
  private retryTimer: number | null = null;
  private pingTimer: number | null = null;
  private lastMessageAt = 0;
  private welcome: Welcome | null = null;

  constructor(private readonly options: ConnectionOptions) {}

  /** The granted role (the server may make a second operator a spectator). */
  get role(): Role {
    return this.welcome?.role ?? this.options.role;
  }

  get lastWelcome(): Welcome | null {
    return this.welcome;
  }

  get isOpen(): boolean {
    return this.socket !== null && this.socket.readyState === WebSocket.OPEN && this.welcome !== null;
  }

  connect(): void {
    if (this.socket !== null) return;
    let socket: WebSocket;
    try {
      socket = new WebSocket(serverUrl("ws", "ws"), [SUBPROTOCOL]);
    } catch (error) {
      this.setStatus("refused", String(error));
      return;
    }
    this.socket = socket;
    this.welcome = null;
    socket.addEventListener("open", () => {
      this.lastMessageAt = performance.now();
      if (socket.protocol !== "" && socket.protocol !== SUBPROTOCOL) {
        this.setStatus("refused", `server speaks ${socket.protocol}, this page ${SUBPROTOCOL}`);
        socket.close(1000);
        return;
      }
      this.sendRaw({
        type: "hello",
        role: this.options.role,
        resume_token: sessionStorage.getItem(RESUME_KEY),
        seat: requestedSeat(),
      });
    });
    socket.addEventListener("message", (event) => this.receive(event));
    socket.addEventListener("close", (event) => this.closed(socket, event));
  }

  /** Send a message if the link is up; returns whether it went out. */
  send(message: ClientMessage): boolean {
    if (!this.isOpen) return false;
    return this.sendRaw(message);
  }

  /** Drop the resume token (the session is over: a reconnect should not resume it). */
  forgetSession(): void {
    sessionStorage.removeItem(RESUME_KEY);
  }

  /** Test hook: drop the socket as a network fault would; the client reconnects itself. */
  dropForTest(): void {
    this.socket?.close(4999, "dropped by test");
  }

  private sendRaw(message: ClientMessage): boolean {
    const socket = this.socket;
    if (socket === null || socket.readyState !== WebSocket.OPEN) return false;
    socket.send(JSON.stringify(message));
    return true;
  }

  private receive(event: MessageEvent): void {
    this.lastMessageAt = performance.now();
    if (typeof event.data !== "string") return;
    let message: ServerMessage;
    try {
      message = JSON.parse(event.data) as ServerMessage;
    } catch {
      console.warn("workcell: unparsable message from server");
      return;
    }
    switch (message.type) {
      case "welcome":
        this.welcome = message;
        if (message.resume_token !== null) {
          sessionStorage.setItem(RESUME_KEY, message.resume_token);
        }
        this.info.attempts = 0;
        this.setStatus("open", null);
        this.startPinging();
        break;
      case "pong":
        this.info.rttMs = Math.max(0, performance.now() - message.t_client * 1000);
        this.options.onStatus(this.info);
        break;
      case "session_ended":
        this.forgetSession();
        break;
      case "error":
        if (message.fatal) this.info.reason = `${message.code}: ${message.message}`;
        break;
      default:
        break;
    }
    this.options.onMessage(message);
  }

  private closed(socket: WebSocket, event: CloseEvent): void {
    if (this.socket !== socket) return;
    this.socket = null;
    this.welcome = null;
    this.stopPinging();
    if (REFUSED_CODES.has(event.code) || this.info.status === "refused") {
      const reason = event.reason !== "" ? event.reason : (this.info.reason ?? `closed (${event.code})`);
      this.setStatus("refused", reason);
      return;
    }
    this.info.attempts += 1;
    // A refused handshake looks like a dropped link to the browser; ask over HTTP once
    // whether the server wants a token this page does not have.
    if (this.info.attempts === 2) void this.probeToken();
    const delay = Math.min(BACKOFF_MAX_MS, BACKOFF_START_MS * 2 ** (this.info.attempts - 1));
    const jittered = delay * (0.75 + Math.random() * 0.5);
    this.setStatus("reconnecting", event.reason !== "" ? event.reason : null);
    if (this.retryTimer !== null) window.clearTimeout(this.retryTimer);
    this.retryTimer = window.setTimeout(() => {
      this.retryTimer = null;
      this.connect();
    }, jittered);
  }

  private async probeToken(): Promise<void> {
    try {
      const reply = await fetch(serverUrl("api/defaults"), { method: "GET" });
      if (reply.status === 401) {
        if (this.retryTimer !== null) window.clearTimeout(this.retryTimer);
        this.retryTimer = null;
        this.setStatus(
          "refused",
          "the server needs its access token: open the address `workcell serve` printed (…?token=…)",
        );
      }
    } catch {
      // The server is down: keep retrying.
    }
  }

  private startPinging(): void {
    this.stopPinging();
    this.pingTimer = window.setInterval(() => {
      if (performance.now() - this.lastMessageAt > SILENCE_LIMIT_MS) {
        this.socket?.close(4998, "no message from the server");
        return;
      }
      this.sendRaw({ type: "ping", t_client: performance.now() / 1000, rtt_ms: this.info.rttMs });
    }, PING_EVERY_MS);
  }

  private stopPinging(): void {
    if (this.pingTimer !== null) window.clearInterval(this.pingTimer);
    this.pingTimer = null;
  }

  private setStatus(status: LinkStatus, reason: string | null): void {
    this.info.status = status;
    this.info.reason = reason;
    this.options.onStatus(this.info);
  }
}
