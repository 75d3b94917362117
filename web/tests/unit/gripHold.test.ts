// Who drives, on the HUD and in the headset (issue 35): the take-over gesture of both grips
// held for a moment fires once per hold and only while armed; the HUD names the driver.

import { describe, expect, it } from "vitest";
import { hudLines } from "../../src/hud/hudText";
import { drivingLabel, GRIP_HOLD_S, GripHold } from "../../src/xr/gripHold";
import { hud } from "./messages";

describe("GripHold", () => {
  it("fires once both grips have been held for a moment, once per hold", () => {
    const hold = new GripHold();
    expect(hold.update(1, 1, 0, true)).toBe(false);
    expect(hold.update(1, 1, GRIP_HOLD_S / 2, true)).toBe(false);
    expect(hold.update(1, 1, GRIP_HOLD_S + 0.01, true)).toBe(true);
    expect(hold.update(1, 1, GRIP_HOLD_S + 1, true)).toBe(false); // still the same hold
    expect(hold.update(0, 1, GRIP_HOLD_S + 1.1, true)).toBe(false); // released
    expect(hold.update(1, 1, 10, true)).toBe(false);
    expect(hold.update(1, 1, 10 + GRIP_HOLD_S + 0.01, true)).toBe(true);
  });

  it("needs both grips, and does nothing while not armed", () => {
    const hold = new GripHold();
    expect(hold.update(1, 0.2, 0, true)).toBe(false);
    expect(hold.update(1, 0.2, 5, true)).toBe(false);
    expect(hold.update(1, 1, 6, false)).toBe(false);
    expect(hold.update(1, 1, 7, false)).toBe(false);
    expect(hold.update(1, 1, 7.1, true)).toBe(true); // armed again while still held long enough
  });
});

describe("who drives", () => {
  it("is on the HUD only when an autonomous driver runs the session", () => {
    expect(hudLines(hud()).some((line) => line.label === "Driving")).toBe(false);
    const watching = hudLines(hud({ driver: "expert" })).find((line) => line.label === "Driving");
    expect(watching?.value).toContain("expert");
    expect(watching?.alert).toBeFalsy();
    const correcting = hudLines(hud({ driver: "expert", taken_over: true })).find((line) => line.label === "Driving");
    expect(correcting).toEqual({ label: "Driving", value: "you (took over from expert)", alert: true });
  });

  it("labels the in-VR menu's item with what choosing it does", () => {
    expect(drivingLabel(null)).toBe("You drive");
    expect(drivingLabel(hud())).toBe("You drive");
    expect(drivingLabel(hud({ driver: "policy:act-1" }))).toBe("Take over from policy:act-1");
    expect(drivingLabel(hud({ driver: "expert", taken_over: true }))).toBe("Hand back to expert");
  });
});
