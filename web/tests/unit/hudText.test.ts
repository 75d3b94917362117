// The end screens' text (src/hud/hudText.ts): a session ended by an error says what went wrong.

import { describe, expect, it } from "vitest";
import { hudLines, sessionEndSummary } from "../../src/hud/hudText";
import type { SessionEnded } from "../../src/protocol";
import { hud } from "./messages";

function ended(overrides: Partial<SessionEnded>): SessionEnded {
  return {
    type: "session_ended",
    session_id: "s1",
    reason: "completed",
    trials: 3,
    successes: 2,
    total_score: 190,
    detail: "",
    stop_note: "",
    ...overrides,
  };
}

describe("hudLines", () => {
  it("shows the stage the task's judge says the running trial reached", () => {
    const lines = hudLines(hud({ stage: "over_zone" }));
    expect(lines.find((line) => line.label === "Stage")?.value).toBe("over zone");
    expect(hudLines(hud({ phase: "countdown" })).some((line) => line.label === "Stage")).toBe(false);
  });
});

describe("the HUD's score", () => {
  it("is the points earned so far, with the time bonus of a success apart", () => {
    const lines = hudLines(hud({ score: 0, time_bonus: 119 }));
    expect(lines.find((line) => line.label === "Score")?.value).toBe("0");
    expect(lines.find((line) => line.label === "Time bonus")?.value).toBe("+119 on success");
    const later = hudLines(hud({ score: 100, boxes_delivered: 1, time_bonus: 40 }));
    expect(later.find((line) => line.label === "Score")?.value).toBe("100");
  });

  it("shows no time bonus before the trial runs", () => {
    const lines = hudLines(hud({ phase: "countdown", score: 0, time_bonus: 0 }));
    expect(lines.some((line) => line.label === "Time bonus")).toBe(false);
  });
});

describe("sessionEndSummary", () => {
  it("says in words who ended the session", () => {
    const lines = sessionEndSummary(ended({ reason: "operator_stop" }));
    expect(lines.map((line) => line.label)).toEqual(["Trials", "Successes", "Total score", "Ended"]);
    expect(lines[3]).toEqual({ label: "Ended", value: "You stopped the session", alert: false });
    expect(lines[1]?.value).toBe("2");
  });

  it("adds the reason whoever stopped it gave", () => {
    const lines = sessionEndSummary(ended({ reason: "admin_stop", stop_note: "the room closes" }));
    expect(lines[3]?.value).toBe("The study's administrator stopped the session: the room closes");
  });

  it("adds the detail of an error and makes it stand out", () => {
    const lines = sessionEndSummary(ended({ reason: "error", detail: "solver exploded" }));
    expect(lines[3]).toEqual({ label: "Ended", value: "The session failed: solver exploded", alert: true });
  });

  it("says what failed when recording stopped, and makes it stand out", () => {
    const detail = "store s.sqlite: the disk holding /data is full (12 KiB free): free space";
    const lines = sessionEndSummary(ended({ reason: "storage_error", detail }));
    expect(lines[3]).toEqual({ label: "Ended", value: `Recording failed: ${detail}`, alert: true });
  });
});
