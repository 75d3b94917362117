// The researcher's views' pure logic: the Sessions page's filters, its address and its CSV
// download (src/pages/sessionFilter.ts), the replay's clock that keeps trial time at the
// wall clock's pace however slowly frames are drawn (src/pages/replayClock.ts), the
// replay's facts (src/pages/replayFacts.ts), the admin's spectate link and the key map's
// remembered state (src/input/keymapPreference.ts).

import { describe, expect, it } from "vitest";
import type { ReplayFacts, SessionSummary, TrialSummary } from "../../src/protocol";
import {
  NO_FILTER,
  NONE,
  TRIALS_CSV_COLUMNS,
  applyFilter,
  filterChoices,
  filterFromHash,
  hashOf,
  trialsCsv,
} from "../../src/pages/sessionFilter";
import { PlaybackMeter, ReplayClock, frameAt } from "../../src/pages/replayClock";
import { factLines } from "../../src/pages/replayFacts";
import { spectateUrl } from "../../src/pages/adminPage";
import { KEYMAP_KEY, keymapOpensAtStart, rememberKeymap } from "../../src/input/keymapPreference";

function trial(id: string, over: Partial<TrialSummary> = {}): TrialSummary {
  return {
    trial_id: id,
    trial_index: 0,
    mode: "practice",
    round: null,
    level: null,
    required_boxes: 1,
    time_limit_s: 120,
    outcome: "success",
    interruption_reason: null,
    elapsed_s: 30.5,
    boxes_delivered: 1,
    score: 190,
    n_frames: 572,
    quality_flags: [],
    included: true,
    exclusion_reason: null,
    started_wall: 0,
    ...over,
  };
}

function session(id: string, operator: string, condition: string | null, step: number | null, trials: TrialSummary[]): SessionSummary {
  return {
    session_id: id,
    mode: "practice",
    operator_id: operator,
    condition,
    study_step: step,
    created_wall: 0,
    ended_wall: 1,
    status: "completed",
    trials,
  };
}

const SESSIONS = [
  session("s1", "p01", "assisted", 1, [trial("t1"), trial("t2", { outcome: "interrupted", interruption_reason: "operator_stop", included: false, exclusion_reason: "incomplete: interrupted (operator_stop)" })]),
  session("s2", "p01", "physical", 2, [trial("t3", { outcome: "timeout", boxes_delivered: 0, score: 0 })]),
  session("s3", "p02", "physical", 1, [trial("t4")]),
  session("s4", "anonymous", null, null, [trial("t5", { outcome: null, included: null })]),
];

describe("the Sessions page's filters", () => {
  it("offer every participant, condition and study step recorded, and (none)", () => {
    expect(filterChoices(SESSIONS)).toEqual({
      participants: ["anonymous", "p01", "p02"],
      conditions: ["assisted", "physical", NONE],
      steps: ["1", "2", NONE],
    });
  });

  it("keep the sessions of a participant, a condition and a study step", () => {
    const ids = (f: typeof NO_FILTER): string[] => applyFilter(SESSIONS, f).map((s) => s.session_id);
    expect(ids(NO_FILTER)).toEqual(["s1", "s2", "s3", "s4"]);
    expect(ids({ ...NO_FILTER, participant: "p01" })).toEqual(["s1", "s2"]);
    expect(ids({ ...NO_FILTER, condition: "physical" })).toEqual(["s2", "s3"]);
    expect(ids({ ...NO_FILTER, participant: "p01", condition: "physical" })).toEqual(["s2"]);
    expect(ids({ ...NO_FILTER, step: "1" })).toEqual(["s1", "s3"]);
    expect(ids({ ...NO_FILTER, condition: NONE })).toEqual(["s4"]);
  });

  it("keep the trials of an outcome or inclusion, dropping sessions left with none", () => {
    const trials = (f: typeof NO_FILTER): string[] => applyFilter(SESSIONS, f).flatMap((s) => s.trials.map((t) => t.trial_id));
    expect(trials({ ...NO_FILTER, trials: "included" })).toEqual(["t1", "t3", "t4"]); // a timeout is included
    expect(trials({ ...NO_FILTER, trials: "not_included" })).toEqual(["t2"]);
    expect(trials({ ...NO_FILTER, trials: "timeout" })).toEqual(["t3"]);
    expect(trials({ ...NO_FILTER, trials: "running" })).toEqual(["t5"]);
    expect(applyFilter(SESSIONS, { ...NO_FILTER, trials: "interrupted" }).map((s) => s.session_id)).toEqual(["s1"]);
  });

  it("live in the page's address, so a link opens the page filtered", () => {
    const filter = { ...NO_FILTER, participant: "p 01&x", trials: "success" as const };
    const hash = hashOf(filter);
    expect(hash).toBe("#/sessions?participant=p+01%26x&trials=success");
    expect(filterFromHash(hash)).toEqual(filter);
    expect(hashOf(NO_FILTER)).toBe("#/sessions");
    expect(filterFromHash("#/sessions")).toEqual(NO_FILTER);
    expect(filterFromHash("#/sessions?trials=nonsense&step=2")).toEqual({ ...NO_FILTER, step: "2" });
  });
});

describe("the shown trials as CSV", () => {
  it("has a row per trial with its session's participant, condition and study step", () => {
    const text = trialsCsv(applyFilter(SESSIONS, { ...NO_FILTER, participant: "p01" }));
    const lines = text.trimEnd().split("\r\n");
    expect(lines[0]).toBe(TRIALS_CSV_COLUMNS.join(","));
    expect(lines).toHaveLength(4);
    const column = (name: string): number => TRIALS_CSV_COLUMNS.indexOf(name as (typeof TRIALS_CSV_COLUMNS)[number]);
    const third = lines[3]?.split(",") ?? [];
    expect([third[column("operator_id")], third[column("condition")], third[column("study_step")]]).toEqual(["p01", "physical", "2"]);
    expect(third[column("outcome")]).toBe("timeout");
    expect(lines[2]).toContain('"incomplete: interrupted (operator_stop)"'.replace(/"/g, ""));
  });

  it("quotes a cell with a comma or a quote, and leaves an unknown value empty", () => {
    const odd = [session("s9", 'p,"9"', null, null, [trial("t9", { quality_flags: ["slow", "jerky"], score: null })])];
    const row = trialsCsv(odd).split("\r\n")[1] ?? "";
    expect(row.startsWith('s9,"p,""9""",,,t9,')).toBe(true);
    expect(row).toContain(",slow;jerky,");
  });
});

describe("the replay's clock", () => {
  it("plays at the wall clock's pace however few frames are drawn", () => {
    const clock = new ReplayClock();
    clock.play(0, 1000);
    // a renderer drawing 4 frames a second: trial time still advances a second per second
    expect(clock.time(1250)).toBeCloseTo(0.25);
    expect(clock.time(3000)).toBeCloseTo(2.0);
  });

  it("is measured by the frames shown against the wall clock", () => {
    const meter = new PlaybackMeter();
    meter.start(0, 0);
    meter.shown(0.2, 500);
    expect(meter.rate()).toBeNull(); // under a second
    meter.shown(0.5, 2000); // a frame a step behind: shown late
    expect(meter.rate()).toBeCloseTo(0.25);
    meter.shown(2.0, 2000);
    expect(meter.rate()).toBeCloseTo(1.0);
  });

  it("skips the frames between two drawn ones", () => {
    const times = Array.from({ length: 301 }, (_, i) => i / 30); // 10 s at 30 frames/s
    const clock = new ReplayClock();
    clock.play(0, 0);
    const shown = [250, 500, 750, 1000].map((ms) => frameAt(times, clock.time(ms)));
    expect(shown).toEqual([7, 15, 22, 30]);
  });

  it("pauses, seeks and changes speed without losing its place", () => {
    const clock = new ReplayClock();
    clock.play(1, 0);
    clock.pause(2000);
    expect(clock.playing).toBe(false);
    expect(clock.time(9000)).toBeCloseTo(3);
    clock.play(3, 9000);
    clock.setSpeed(2, 10000);
    expect(clock.time(11000)).toBeCloseTo(6);
    clock.seek(0.5, 11000);
    expect(clock.time(11500)).toBeCloseTo(1.5);
    expect(clock.time(10999.5 - 2000)).toBeCloseTo(0.5); // a frame stamped before the seek never goes back
  });
});

describe("the replay's facts", () => {
  it("say who ran the trial, in which condition and step, and how it ended", () => {
    const facts: ReplayFacts = {
      operator_id: "p01",
      condition: "physical",
      study_step: 2,
      mode: "challenge",
      round: 1,
      level: 2,
      required_boxes: 2,
      time_limit_s: 120,
      outcome: "interrupted",
      interruption_reason: "operator_stop",
      elapsed_s: 12.34,
      boxes_delivered: 1,
      score: 100,
      included: false,
      exclusion_reason: "incomplete: interrupted (operator_stop)",
    };
    expect(Object.fromEntries(factLines(facts))).toEqual({
      participant: "p01",
      condition: "physical",
      "study step": "2",
      mode: "challenge, round 1, level 2",
      outcome: "interrupted (operator_stop)",
      duration: "12.3 s of 120 s",
      boxes: "1/2",
      score: "100",
      included: "no: incomplete: interrupted (operator_stop)",
    });
  });
});

describe("the admin's spectate link", () => {
  it("opens the participant's seat read-only in the teleoperation view, with the admin's token", () => {
    const url = new URL(spectateUrl("p01", "https://lab.example:8443/app/?token=old&role=spectator#/admin", "ADMIN"));
    expect(url.pathname).toBe("/app/");
    expect(url.hash).toBe("#/teleop");
    expect(Object.fromEntries(url.searchParams)).toEqual({ token: "ADMIN", role: "spectator", seat: "p01" });
    expect(new URL(spectateUrl("p02", "http://127.0.0.1:8000/#/admin", null)).searchParams.has("token")).toBe(false);
  });
});

describe("the key map", () => {
  it("opens the first time, is folded after that, and keeps the operator's choice", () => {
    const kept = new Map<string, string>();
    const storage = { getItem: (k: string) => kept.get(k) ?? null, setItem: (k: string, v: string) => void kept.set(k, v) };
    expect(keymapOpensAtStart(storage)).toBe(true);
    expect(keymapOpensAtStart(storage)).toBe(false);
    rememberKeymap(storage, true);
    expect(keymapOpensAtStart(storage)).toBe(true);
    rememberKeymap(storage, false);
    expect(keymapOpensAtStart(storage)).toBe(false);
    expect(kept.get(KEYMAP_KEY)).toBe("folded");
  });
});
