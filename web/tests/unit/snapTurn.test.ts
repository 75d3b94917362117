// Snap turns (src/xr/snapTurn.ts): a flick asks the server for one snap and blacks the view
// out until the drawn base has turned and stands still again.

import { describe, expect, it } from "vitest";
import { MAX_BLACKOUT_S, SnapTurn } from "../../src/xr/snapTurn";

describe("SnapTurn", () => {
  it("asks for one snap per flick, in the stick's direction, however long it is held", () => {
    const snap = new SnapTurn();
    expect(snap.update(0.9, 0, 0)).toEqual({ ask: "snap_right", blackout: true });
    for (let i = 1; i < 400; i += 1) expect(snap.update(0.9, i / 72, 0).ask).toBeNull();
    expect(snap.snaps).toBe(1);
    snap.update(0, 6, 0); // the stick comes back: armed again
    expect(snap.update(-0.8, 6.1, 0).ask).toBe("snap_left");
    expect(snap.snaps).toBe(2);
  });

  it("keeps the view blacked out until the drawn base has turned and stopped", () => {
    const snap = new SnapTurn();
    snap.update(1, 0, 0);
    expect(snap.update(0, 0.1, 0).blackout).toBe(true); // not turning yet (latency)
    expect(snap.update(0, 0.3, 1.1).blackout).toBe(true); // turning
    expect(snap.update(0, 0.6, 0.4).blackout).toBe(true); // braking
    expect(snap.update(0, 0.8, 0.01).blackout).toBe(false); // still
    expect(snap.active).toBe(false);
  });

  it("clears the view after a while even if no turn was ever drawn, and ignores small deflections", () => {
    const snap = new SnapTurn();
    snap.update(1, 0, 0);
    expect(snap.update(0, MAX_BLACKOUT_S - 0.1, 0).blackout).toBe(true);
    expect(snap.update(0, MAX_BLACKOUT_S + 0.1, 0).blackout).toBe(false);
    expect(snap.update(0.5, 5, 0)).toEqual({ ask: null, blackout: false });
    expect(snap.snaps).toBe(1);
  });
});
