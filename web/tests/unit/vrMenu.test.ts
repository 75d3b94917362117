// The in-VR menu's logic (src/xr/vrMenu.ts) and recentering (src/xr/recenter.ts).

import { describe, expect, it } from "vitest";
import type { Pose } from "../../src/protocol";
import { MENU_ITEMS, MenuState } from "../../src/xr/vrMenu";
import type { MenuInput } from "../../src/xr/vrMenu";
import { applyRecenter, headingOf, NO_RECENTER, recenterOn, recenterPoint, undo } from "../../src/xr/recenter";

const idle: MenuInput = { open: false, choose: false, back: false, stickY: 0 };

function press(menu: MenuState, change: Partial<MenuInput>): ReturnType<MenuState["update"]> {
  const chosen = menu.update({ ...idle, ...change });
  menu.update(idle);
  return chosen;
}

describe("the in-VR menu", () => {
  it("opens on X, moves on stick flicks and chooses on A", () => {
    const menu = new MenuState();
    expect(press(menu, { choose: true })).toBeNull(); // closed: A does nothing
    press(menu, { open: true });
    expect(menu.open).toBe(true);
    menu.update({ ...idle, stickY: -1 }); // down
    menu.update({ ...idle, stickY: -0.9 }); // held: no second step
    menu.update(idle);
    expect(menu.index).toBe(1);
    press(menu, { stickY: 1 }); // up
    press(menu, { stickY: 1 }); // up again wraps to the last item
    expect(menu.index).toBe(MENU_ITEMS.length - 1);
    press(menu, { stickY: -1 });
    press(menu, { stickY: -1 });
    expect(MENU_ITEMS[menu.index]).toBe("recenter_view");
    expect(press(menu, { choose: true })).toBe("recenter_view");
    expect(menu.open).toBe(false);
  });

  it("reopens where it was for a choice that asks to be confirmed (Stop session)", () => {
    const menu = new MenuState();
    press(menu, { open: true });
    const stop = MENU_ITEMS.indexOf("stop_session");
    for (let i = 0; i < stop; i += 1) press(menu, { stickY: -1 });
    expect(press(menu, { choose: true })).toBe("stop_session");
    menu.reopen();
    expect(menu.open).toBe(true);
    expect(MENU_ITEMS[menu.index]).toBe("stop_session");
    expect(press(menu, { choose: true })).toBe("stop_session"); // the confirmation
    expect(MENU_ITEMS).toContain("pause");
  });

  it("closes on B or X without choosing", () => {
    const menu = new MenuState();
    press(menu, { open: true });
    expect(press(menu, { back: true })).toBeNull();
    expect(menu.open).toBe(false);
    press(menu, { open: true });
    press(menu, { open: true });
    expect(menu.open).toBe(false);
  });
});

describe("recentering", () => {
  const turned = (yaw: number, x = 0.3, z = -0.2): Pose => [x, 1.6, z, Math.cos(yaw / 2), 0, Math.sin(yaw / 2), 0];

  it("reads a headset's heading", () => {
    expect(headingOf(turned(0))).toBeCloseTo(0, 9);
    expect(headingOf(turned(0.7))).toBeCloseTo(0.7, 9);
    expect(headingOf(turned(-2.5))).toBeCloseTo(-2.5, 9);
  });

  it("makes the headset's heading forward and keeps where it is", () => {
    const headset = turned(1.1);
    const r = recenterOn(headset);
    const after = applyRecenter(headset, r);
    expect(headingOf(after)).toBeCloseTo(0, 9);
    after.slice(0, 3).forEach((v, i) => expect(v).toBeCloseTo(headset[i] ?? Number.NaN, 9));
  });

  it("turns a controller about the headset's vertical axis, and back", () => {
    const r = recenterOn(turned(Math.PI / 2, 0, 0)); // facing -x
    // a controller 0.5 m in front of the operator (towards -x) ends up in front (towards -z)
    const controller: Pose = [-0.5, 1.2, 0, 1, 0, 0, 0];
    const moved = applyRecenter(controller, r);
    expect(moved[0]).toBeCloseTo(0, 9);
    expect(moved[2]).toBeCloseTo(-0.5, 9);
    const back = recenterPoint([moved[0], moved[1], moved[2]], undo(r));
    expect(back[0]).toBeCloseTo(-0.5, 9);
    expect(back[2]).toBeCloseTo(0, 9);
    expect(applyRecenter(controller, NO_RECENTER)).toBe(controller);
  });
});
