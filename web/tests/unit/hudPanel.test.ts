// The XR HUD panel's note (src/hud/hudPanel.ts): what the trial asks, wrapped under the title.

import { describe, expect, it } from "vitest";
import { wrapText } from "../../src/hud/hudPanel";

const chars = (s: string): number => s.length; // one unit per character

describe("wrapText (what the trial asks, under the XR HUD's title)", () => {
  it("breaks at spaces into rows no wider than the width", () => {
    const rows = wrapText("Put the box on the middle shelf.", 12, 5, chars);
    expect(rows).toEqual(["Put the box", "on the", "middle", "shelf."]);
    expect(rows.every((row) => row.length <= 12)).toBe(true);
  });

  it("keeps the words in order and loses none when the rows suffice", () => {
    const text = "Sort the box onto the table whose zone has its colour.";
    expect(wrapText(text, 20, 4, chars).join(" ")).toBe(text);
  });

  it("cuts the last row with an ellipsis when the text needs more rows", () => {
    const rows = wrapText("one two three four five six seven", 9, 2, chars);
    expect(rows).toHaveLength(2);
    expect(rows[0]).toBe("one two");
    expect(rows[1]?.endsWith("…")).toBe(true);
    expect(rows[1]?.length).toBeLessThanOrEqual(9);
  });

  it("puts a word longer than the width on its own row, and nothing for no text", () => {
    expect(wrapText("palletize", 4, 2, chars)).toEqual(["palletize"]);
    expect(wrapText("  ", 10, 2, chars)).toEqual([]);
  });
});
