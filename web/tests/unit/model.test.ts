// How the client applies the server's messages (src/net/model.ts): State and its HUD,
// task events, errors with their structured problem, session start and end.

import { describe, expect, it } from "vitest";
import { ClientModel, EVENT_HISTORY } from "../../src/net/model";
import { grasp, hud, problem, state, trialEnded, trialStarted } from "./messages";

describe("ClientModel.apply", () => {
  it("follows a pause from its paused event to its resumed one, and forgets it at a new trial", () => {
    const model = new ClientModel();
    model.apply({ type: "event", kind: "paused", trial_index: 0, t_sim: 1.5 });
    expect(model.paused).toBe(true);
    model.apply({ type: "event", kind: "resumed", trial_index: 0, t_sim: 1.5, paused_s: 3 });
    expect(model.paused).toBe(false);
    model.apply({ type: "event", kind: "paused", trial_index: 0, t_sim: 2 });
    model.apply(trialStarted(1));
    expect(model.paused).toBe(false);
  });

  it("keeps the waiting line's word until the session starts", () => {
    const model = new ClientModel();
    const queued = { type: "queued", position: 2, waiting: 3, message: "queued: position 2 of 3" } as const;
    expect(model.apply(queued)).toEqual({ kind: "queued", message: "queued: position 2 of 3" });
    expect(model.queued?.position).toBe(2);
    model.apply({ type: "session_started", session_id: "s1", mode: "practice", operator_id: "a", settings: {} });
    expect(model.queued).toBeNull();
    model.apply(queued);
    model.apply({ type: "error", code: "not_allowed", message: "start_session: you have run every session", fatal: false, problem: null });
    expect(model.queued).toBeNull(); // a start refused after waiting waits no more
  });

  it("keeps the newest State and its HUD, dropping older ones as stale", () => {
    const model = new ClientModel();
    expect(model.apply(state(2, { hud: hud({ remaining_s: 50 }) }))).toBeNull();
    model.apply(state(1, { hud: hud({ remaining_s: 99 }) }));
    expect(model.state?.seq).toBe(2);
    expect(model.hud?.remaining_s).toBe(50);
    expect(model.stats).toEqual({ states: 2, stale: 1 });
  });

  it("keeps the last HUD when a State carries none", () => {
    const model = new ClientModel();
    model.apply(state(1, { hud: hud({ score: 42 }) }));
    model.apply(state(2, { hud: null }));
    expect(model.state?.seq).toBe(2);
    expect(model.hud?.score).toBe(42);
  });

  it("reads the grasp from the typed event's engaged field", () => {
    const model = new ClientModel();
    expect(model.apply(grasp(true))).toEqual({ kind: "task_event", event: grasp(true) });
    expect(model.holding).toBe(true);
    model.apply(grasp(false));
    expect(model.holding).toBe(false);
    model.apply(grasp(true));
    model.apply(trialStarted(1));
    expect(model.holding).toBe(false);
  });

  it("keeps the trial end until the next trial starts", () => {
    const model = new ClientModel();
    const ended = trialEnded({ outcome: "timeout", score: 0 });
    model.apply(ended);
    expect(model.lastTrialEnd).toEqual(ended);
    model.apply({ type: "event", kind: "countdown_started", trial_index: 1, t_sim: -3, seconds: 3 });
    expect(model.lastTrialEnd).toEqual(ended);
    model.apply(trialStarted(1));
    expect(model.lastTrialEnd).toBeNull();
  });

  it("keeps a bounded history of events", () => {
    const model = new ClientModel();
    for (let i = 0; i < EVENT_HISTORY + 5; i += 1) model.apply(grasp(i % 2 === 0));
    expect(model.events).toHaveLength(EVENT_HISTORY);
  });

  it("passes an error's structured problem on and records the error", () => {
    const model = new ClientModel();
    const refused = problem(["input", "left", "grip"], 2, "must be from 0 to 1");
    const change = model.apply({ type: "error", code: "invalid_value", message: refused.message, fatal: false, problem: refused });
    expect(change).toEqual({ kind: "server_error", code: "invalid_value", message: refused.message, problem: refused });
    expect(model.errors).toEqual([{ code: "invalid_value", message: refused.message }]);
  });

  it("passes a rejected configuration's problems on unchanged", () => {
    const model = new ClientModel();
    const problems = [problem(["task", "mode"], "marathon", "must be one of 'practice'")];
    expect(model.apply({ type: "config_rejected", problems })).toEqual({ kind: "config_rejected", problems });
  });

  it("starts a session afresh and ends it", () => {
    const model = new ClientModel();
    model.apply(grasp(true));
    model.apply(state(5));
    const started = model.apply({
      type: "session_started",
      session_id: "s1",
      mode: "collection",
      operator_id: "op",
      settings: {},
    });
    expect(started).toEqual({ kind: "session" });
    expect(model.sessionActive).toBe(true);
    expect(model.events).toHaveLength(0);
    expect(model.state).toBeNull();
    model.apply({ type: "session_ended", session_id: "s1", reason: "operator_stop", trials: 1, successes: 1, total_score: 190, detail: "", stop_note: "" });
    expect(model.sessionActive).toBe(false);
    expect(model.ended?.total_score).toBe(190);
  });

  it("takes the running session from Welcome after a reconnect", () => {
    const model = new ClientModel();
    model.apply(state(9));
    model.apply({ type: "welcome", protocol: 1, role: "operator", session_id: "s2", resume_token: "t", grace_s: 10, seat: "1" });
    expect(model.sessionId).toBe("s2");
    expect(model.state).toBeNull();
  });
});
