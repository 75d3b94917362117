// A rejected setting is shown beside the field its structured path names (src/pages/settingsForm.ts).

import { describe, expect, it } from "vitest";
import { fieldFor, placeProblems } from "../../src/pages/settingsForm";
import { problem } from "./messages";

const KEYS = ["task.mode", "task.level_boxes", "task.level_time_limits_s", "world.conveyor.speed", "seed"];

describe("placing field problems", () => {
  it("puts a problem on the setting its path names", () => {
    expect(fieldFor(problem(["world", "conveyor", "speed"], 9, "must be between 0.01 and 1 m/s"), KEYS)).toBe(
      "world.conveyor.speed",
    );
    expect(fieldFor(problem(["seed"], "x", "must be a whole number"), KEYS)).toBe("seed");
  });

  it("puts a list item's problem on its list", () => {
    expect(fieldFor(problem(["task", "level_boxes", 1], 0, "must be a whole number from 1 to 20"), KEYS)).toBe(
      "task.level_boxes",
    );
  });

  it("does not match a setting whose name only starts the same way", () => {
    // task.level_boxes must not catch task.level_boxes_extra (a prefix match would).
    expect(fieldFor(problem(["task", "level_boxes_extra"], 1, "unknown setting"), KEYS)).toBeNull();
    expect(fieldFor(problem([], null, "config file is not valid TOML"), KEYS)).toBeNull();
  });

  it("groups the lines by field in the server's order and keeps the rest apart", () => {
    const first = problem(["task", "level_boxes", 0], 0, "must be from 1 to 20");
    const second = problem(["task", "level_boxes", 2], 99, "must be from 1 to 20");
    const unknown = problem(["task", "colour"], "red", "unknown setting; allowed here: mode");
    const placed = placeProblems([first, unknown, second], KEYS);
    expect([...placed.byField]).toEqual([["task.level_boxes", [first.message, second.message]]]);
    expect(placed.general).toEqual([unknown.message]);
  });
});
