// End to end on the desktop page with keyboard and mouse only: set up a practice session,
// then the same scripted operator as in VR delivers the box, pressing keys the way a
// person would (WASD/QE drive, G/H hold the grips, Z turns the palms in, F/J close the
// grippers, comma/period bring the hands together or apart) and dragging the mouse / turning
// the wheel to move the gripped hands. Prints "RESULT {json}" for the pytest wrapper.
//
//   npm run build:e2e && node build/e2e/tests/e2e/desktop_delivery.js http://127.0.0.1:8000   (in web/)

import path from "node:path";
import type { Keyboard } from "playwright-core";
import type { Pose } from "../../src/protocol";
import { PATIENCE_MS, check, checkDrawn, runScript, sleep, waitFor, waitForFrames } from "./lib.js";
import type { DebugSnapshot } from "./lib.js";
import { ScriptedOperator, controllerCorrections } from "./operator.js";
import type { Decision, Drive, Observation } from "./operator.js";
import { startSession } from "./flow.js";
import { checkDelivered, deliver, deliveryResult } from "./delivery.js";

const TICK_MS = 15;
const TAP_MS = 110; // a key tap near the goal...
const SETTLE_MS = 250; // ...then let the base stop before looking again
const METRES_PER_PIXEL = 0.0015; // src/input/desktop.ts MOUSE_METRES_PER_PIXEL
const METRES_PER_WHEEL = 0.0004; // src/input/desktop.ts WHEEL_METRES_PER_UNIT
const PALM_IN_Z = Math.SQRT1_2; // quaternion z of a controller turned palm-in

function observeJs(): { snap: DebugSnapshot; bodies: Record<string, Pose> } {
  const workcell = window.__workcell;
  if (workcell === undefined) throw new Error("no window.__workcell");
  return { snap: workcell.snapshot(), bodies: workcell.bodies() };
}

/** Keys held down now, pressed and released only on change. */
class Keys {
  readonly down = new Set<string>();
  /** Every key ever used, for the report. */
  readonly pressed = new Set<string>();

  constructor(private readonly keyboard: Keyboard) {}

  async set(wanted: ReadonlySet<string>): Promise<void> {
    for (const key of [...this.down]) {
      if (!wanted.has(key)) {
        await this.keyboard.up(key);
        this.down.delete(key);
      }
    }
    for (const key of wanted) {
      if (!this.down.has(key)) {
        await this.keyboard.down(key);
        this.down.add(key);
        this.pressed.add(key);
      }
    }
  }
}

/** Drive keys for a stick decision: a component beyond `deadband` holds its key; Shift
 * (slow) unless some component asks for more than half speed. */
function driveKeys(drive: Drive, wanted: Set<string>): void {
  const { forward, left, turn } = drive;
  const deadband = 0.05;
  if (forward > deadband) wanted.add("w");
  if (forward < -deadband) wanted.add("s");
  if (left > deadband) wanted.add("a");
  if (left < -deadband) wanted.add("d");
  if (turn > deadband) wanted.add("e");
  if (turn < -deadband) wanted.add("q");
  const fast = Math.max(Math.abs(forward), Math.abs(left), Math.abs(turn)) > 0.5;
  if (wanted.size > 0 && !fast) wanted.add("Shift");
}

await runScript("desktop_delivery", async ({ url, page, artifacts }) => {
  await startSession(page, url, { operatorId: "e2e-desktop", query: { quality: "low" }, artifacts });
  const canvas = page.locator("canvas.viewer-canvas");
  const box = await canvas.boundingBox();
  check(box !== null, "no 3D view on the teleop page");
  const centre = { x: box.x + box.width / 2, y: box.y + box.height / 2 };
  await page.mouse.click(centre.x, centre.y); // focus the view

  // The key map is on screen.
  const keymap = (await page.textContent("#keymap")) ?? "";
  check(keymap.includes("W A S D") && keymap.includes("G / H"), "the key map is not shown");
  await waitForFrames(page);
  await checkDrawn(page, path.join(artifacts, "desktop-view.png"));

  // C toggles the view; both views are drawn.
  await page.keyboard.press("c");
  await waitFor(page, (s) => s.teleop?.view === "first", { what: "C to switch to first person" });
  await waitForFrames(page);
  await checkDrawn(page, path.join(artifacts, "desktop-first-person.png"));
  await page.keyboard.press("c");
  await waitFor(page, (s) => s.teleop?.view === "third", { what: "C to switch back" });

  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the countdown to end" });
  await checkDrawn(page, path.join(artifacts, "hud-running.png"), page.locator("#hud"));

  const keys = new Keys(page.keyboard);
  const operator = new ScriptedOperator({ onOff: true, lead: 0.25, tolerance: 0.03, slowDrive: true });
  let mouse: { x: number; y: number } | null = null; // while the left button is held
  const act = async (decision: Decision, obs: Observation, snap: DebugSnapshot): Promise<number> => {
    const sent = snap.teleop?.last_input ?? null;
    const wanted = new Set<string>();
    driveKeys(decision.drive, wanted);
    if (decision.grip) wanted.add("g").add("h");
    if (decision.trigger) wanted.add("f").add("j");
    const following = obs.following[0] && obs.following[1];
    if (decision.grip && decision.palmsIn && following && sent !== null) {
      const zs = [sent.left.pose?.[6] ?? 0, -(sent.right.pose?.[6] ?? 0)];
      if (Math.min(...zs) < PALM_IN_Z - 0.01) wanted.add("z");
    }
    // Differential (hands together/apart) by keys, common motion by the mouse.
    const [cl, cr] = controllerCorrections(obs, decision.targets, 0.8, 0.05);
    if (cl !== null && cr !== null && following) {
      const together = (cl[0] - cr[0]) / 2;
      if (together > 0.004) wanted.add("Comma");
      if (together < -0.004) wanted.add("Period");
      const common = [0, 1, 2].map((k) => ((cl[k] ?? 0) + (cr[k] ?? 0)) / 2) as [number, number, number];
      if (mouse === null) {
        mouse = { ...centre };
        await page.mouse.move(mouse.x, mouse.y);
        await page.mouse.down();
      }
      const dx = Math.round(common[0] / METRES_PER_PIXEL);
      const dy = Math.round(common[2] / METRES_PER_PIXEL);
      if (dx !== 0 || dy !== 0) {
        const nx: number = mouse.x + dx;
        const ny: number = mouse.y + dy;
        if (nx < box.x + 5 || nx > box.x + box.width - 5 || ny < box.y + 5 || ny > box.y + box.height - 5) {
          // Out of room: let go of the button, recentre, press again (no motion while up).
          await page.mouse.up();
          mouse = { ...centre };
          await page.mouse.move(mouse.x, mouse.y);
          await page.mouse.down();
        } else {
          mouse = { x: nx, y: ny };
          await page.mouse.move(mouse.x, mouse.y);
        }
      }
      const wheel = Math.round(-common[1] / METRES_PER_WHEEL);
      if (Math.abs(wheel) >= 5) await page.mouse.wheel(0, wheel);
    } else if (mouse !== null && !decision.grip) {
      await page.mouse.up();
      mouse = null;
    }
    await keys.set(wanted);
    if (decision.drive.fine && ["w", "a", "s", "d", "q", "e"].some((k) => wanted.has(k))) {
      await sleep(TAP_MS);
      for (const k of ["w", "a", "s", "d", "q", "e"]) wanted.delete(k);
      await keys.set(wanted);
      const settle = Math.max(SETTLE_MS, operator.lead * 1000); // until the base has stopped
      await sleep(settle);
      return TAP_MS + settle;
    }
    return 0;
  };
  const run = await deliver(page, artifacts, operator, {
    prefix: "desktop",
    tickMs: TICK_MS,
    debugEveryMs: 500,
    adaptLead: true,
    look: () => page.evaluate(observeJs),
    act,
    debug: (decision, _obs, snap) => {
      const sent = snap.teleop?.last_input;
      const drive = JSON.stringify(decision.drive, (_k, v: unknown) => (typeof v === "number" ? Number(v.toFixed(2)) : v));
      return `drive=${drive} keys=${[...keys.down]} stick=${JSON.stringify(sent?.left.stick)}/${JSON.stringify(sent?.right.stick)}`;
    },
  });
  await keys.set(new Set());
  if (mouse !== null) await page.mouse.up();
  await page.waitForSelector("#end-screen.campaign-end", { timeout: PATIENCE_MS });
  await checkDrawn(page, path.join(artifacts, "end-screen.png"), page.locator("#end-screen"));
  await checkDrawn(page, path.join(artifacts, "view-end.png"));

  const result = {
    ...deliveryResult(run),
    keys_used: [...keys.pressed].sort(),
    source: run.last.teleop?.last_input?.source ?? null,
  };
  console.log(`RESULT ${JSON.stringify(result)}`);
  checkDelivered(run, "keyboard");
});
