// The scripted operator's decisions as a person at a desktop makes them: keys for the drive
// (W/A/S/D, Q/E, Shift slow), the grips (G/H), the grippers (F/J) and the palms (Z); the
// hands together or apart by tapping comma / period, and the gripped hands moved by
// dragging the mouse and turning the wheel. desktop_delivery.ts and palletize_desktop.ts
// drive with it.
//
// A loaded machine draws a frame every few hundred ms and the loop that looks and acts
// takes as long, so a key held from one look to the next would move the hands far past
// their targets. The hands are moved the way a person with a slow screen moves them: a
// correction sized to what is left (a tap as long as that distance takes, slow with Shift
// when it is short), then a wait of one loop latency (the operator's `lead`) to see it
// before the next.

import type { Keyboard, Page } from "playwright-core";
import { sleep } from "./lib.js";
import type { DebugSnapshot } from "./lib.js";
import { controllerCorrections } from "./operator.js";
import type { Decision, Drive, Observation, ScriptedOperator } from "./operator.js";

const TAP_MS = 110; // a drive key tap near the goal...
const SETTLE_MS = 250; // ...then let the base stop before looking again
const METRES_PER_PIXEL = 0.0015; // src/input/desktop.ts MOUSE_METRES_PER_PIXEL
const METRES_PER_WHEEL = 0.0004; // src/input/desktop.ts WHEEL_METRES_PER_UNIT
const SQUEEZE_SPEED = 0.1; // src/input/desktop.ts SQUEEZE_SPEED (m/s per hand)
const SLOW = 0.3; // src/input/desktop.ts SLOW (Shift)
const SLOW_SQUEEZE_BELOW = 0.015; // m: a squeeze shorter than this is tapped with Shift
const SQUEEZE_TAP_MS: [number, number] = [40, 250]; // shortest and longest squeeze tap
const PALM_IN_Z = Math.SQRT1_2; // quaternion z of a controller turned palm-in
export const DRIVE_KEYS = ["w", "a", "s", "d", "q", "e"];

interface Area {
  x: number;
  y: number;
  width: number;
  height: number;
}

/** Drive keys for a stick decision: a component beyond `deadband` holds its key; Shift
 * (slow) unless some component asks for more than half speed. */
export function driveKeys(drive: Drive, wanted: Set<string>): void {
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

/** Keys held down now, pressed and released only on change. */
export class Keys {
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

  /** Hold `key` for `ms` (with Shift if `slow`) on top of the keys down, then let go. */
  async tap(key: string, ms: number, slow: boolean): Promise<void> {
    const shift = slow && !this.down.has("Shift");
    if (shift) await this.keyboard.down("Shift");
    await this.keyboard.down(key);
    this.pressed.add(key);
    await sleep(ms);
    await this.keyboard.up(key);
    if (shift) await this.keyboard.up("Shift");
  }
}

/** Hide the key map if it is shown: it covers part of the 3D view, and a drag that starts
 * on it does not move the hands (as a person who knows the keys hides it). */
export async function hideKeymap(page: Page): Promise<void> {
  const hide = page.locator("#keymap:not(.hidden) .keymap-close");
  if ((await hide.count()) > 0) await hide.click();
  await page.locator("#keymap.hidden").waitFor({ state: "attached" });
}

/** Acts on the scripted operator's decisions with the keyboard and the mouse (drags start
 * at the centre of `view`: hide the key map first, {@link hideKeymap}). */
export class DesktopHands {
  readonly keys: Keys;
  private mouse: { x: number; y: number } | null = null; // while the left button is held
  private handsSettleAt = 0; // wall time (ms) the last hand correction can be seen
  private readonly centre: { x: number; y: number };
  /** The last hand correction, for the trace: mouse drag (px), wheel, squeeze tap. */
  lastCorrection = "";

  constructor(
    private readonly page: Page,
    private readonly view: Area,
    private readonly operator: ScriptedOperator,
  ) {
    this.keys = new Keys(page.keyboard);
    this.centre = { x: view.x + view.width / 2, y: view.y + view.height / 2 };
  }

  /** Press what `decision` asks; returns the ms spent waiting on purpose (taps, settling),
   * which is not the loop's latency. */
  async act(decision: Decision, obs: Observation, snap: DebugSnapshot): Promise<number> {
    const sent = snap.teleop?.last_input ?? null;
    const wanted = new Set<string>();
    driveKeys(decision.drive, wanted);
    const driving = wanted.size > 0;
    if (decision.grip) wanted.add("g").add("h");
    if (decision.trigger) wanted.add("f").add("j");
    const following = obs.following[0] && obs.following[1];
    if (decision.grip && decision.palmsIn && following && sent !== null) {
      const zs = [sent.left.pose?.[6] ?? 0, -(sent.right.pose?.[6] ?? 0)];
      if (Math.min(...zs) < PALM_IN_Z - 0.01) wanted.add("z");
    }
    let squeeze: { key: string; ms: number; slow: boolean } | null = null;
    const [cl, cr] = controllerCorrections(obs, decision.targets, 0.8, 0.05);
    if (cl !== null && cr !== null && following) {
      if (this.mouse === null) {
        this.mouse = { ...this.centre };
        await this.page.mouse.move(this.mouse.x, this.mouse.y);
        await this.page.mouse.down();
      }
      if (performance.now() >= this.handsSettleAt) {
        // Differential (hands together/apart) by a timed key tap, common motion by the mouse.
        const together = (cl[0] - cr[0]) / 2;
        if (Math.abs(together) > 0.004) {
          const slow = !driving && Math.abs(together) < SLOW_SQUEEZE_BELOW;
          const ms = (1000 * Math.abs(together)) / (SQUEEZE_SPEED * (slow ? SLOW : 1));
          const [shortest, longest] = SQUEEZE_TAP_MS;
          squeeze = { key: together > 0 ? "Comma" : "Period", ms: Math.min(longest, Math.max(shortest, ms)), slow };
        }
        const common = [0, 1, 2].map((k) => ((cl[k] ?? 0) + (cr[k] ?? 0)) / 2) as [number, number, number];
        const moved = await this.moveMouse(common);
        this.lastCorrection = `common=${common.map((v) => (100 * v).toFixed(1)).join(",")}cm squeeze=${squeeze?.key ?? "-"}:${squeeze?.ms.toFixed(0) ?? 0}ms mouse=${this.mouse?.x},${this.mouse?.y} moved=${moved}`;
        if (moved || squeeze !== null) this.handsSettleAt = performance.now() + this.operator.lead * 1000;
      }
    } else if (this.mouse !== null && !decision.grip) {
      await this.page.mouse.up();
      this.mouse = null;
    }
    await this.keys.set(wanted);
    let waited = 0;
    if (squeeze !== null) {
      await this.keys.tap(squeeze.key, squeeze.ms, squeeze.slow);
      waited += squeeze.ms;
    }
    if (decision.drive.fine && DRIVE_KEYS.some((k) => wanted.has(k))) {
      await sleep(TAP_MS);
      for (const k of DRIVE_KEYS) wanted.delete(k);
      await this.keys.set(wanted);
      const settle = Math.max(SETTLE_MS, this.operator.lead * 1000); // until the base has stopped
      await sleep(settle);
      waited += TAP_MS + settle;
    }
    return waited;
  }

  /** Let go of every key and the mouse button. */
  async release(): Promise<void> {
    await this.keys.set(new Set());
    if (this.mouse !== null) await this.page.mouse.up();
    this.mouse = null;
  }

  /** Drag the held mouse by `common` (m: x right, y up by the wheel, z toward the person);
   * whether it moved. */
  private async moveMouse(common: [number, number, number]): Promise<boolean> {
    const mouse = this.mouse;
    if (mouse === null) return false;
    const { view, centre } = this;
    const dx = Math.round(common[0] / METRES_PER_PIXEL);
    const dy = Math.round(common[2] / METRES_PER_PIXEL);
    let moved = false;
    if (dx !== 0 || dy !== 0) {
      moved = true;
      const nx = mouse.x + dx;
      const ny = mouse.y + dy;
      if (nx < view.x + 5 || nx > view.x + view.width - 5 || ny < view.y + 5 || ny > view.y + view.height - 5) {
        // Out of room: let go of the button, recentre, press again (no motion while up).
        await this.page.mouse.up();
        this.mouse = { ...centre };
        await this.page.mouse.move(centre.x, centre.y);
        await this.page.mouse.down();
        moved = false;
      } else {
        this.mouse = { x: nx, y: ny };
        await this.page.mouse.move(nx, ny);
      }
    }
    const wheel = Math.round(-common[1] / METRES_PER_WHEEL);
    if (Math.abs(wheel) >= 5) {
      await this.page.mouse.wheel(0, wheel);
      moved = true;
    }
    return moved;
  }
}
