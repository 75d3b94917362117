// End to end in an emulated Meta Quest 3 (IWER): set up a practice session, enter
// immersive-vr, drive the base with the left thumbstick, toggle the view with B, then
// a scripted operator takes both grips, moves the controllers, closes both triggers and
// delivers the box. Prints "RESULT {json}" for the pytest wrapper, which checks the store.
//
//   npm run build:e2e && node build/e2e/tests/e2e/xr_delivery.js http://127.0.0.1:8000   (in web/)

import { writeFileSync } from "node:fs";
import path from "node:path";
import type { EmulatedDevice } from "../../src/xr/emulate";
import { check, checkDrawn, imageStats, log, runScript, sleep, waitFor } from "./lib.js";
import type { DebugSnapshot } from "./lib.js";
import { ScriptedOperator, controllerCorrections } from "./operator.js";
import type { Decision, Observation, Vec3 } from "./operator.js";
import { startSession } from "./flow.js";
import { checkDelivered, deliver, deliveryResult } from "./delivery.js";
import type { Seen } from "./delivery.js";

type Quat = [number, number, number, number];
type Side = "left" | "right";

/** What to set on one emulated controller (left out: unchanged). */
interface HandCommand {
  pos?: Vec3;
  quat?: Quat;
  grip?: number;
  trigger?: number;
  stick?: [number, number];
  buttons?: Record<string, number>;
}

interface DeviceCommand {
  headset?: { pos: Vec3; quat: Quat };
  hands?: Partial<Record<Side, HandCommand>>;
}


const TICK_MS = 20;
const REST: Record<Side, Vec3> = { left: [-0.2, 1.0, -0.3], right: [0.2, 1.0, -0.3] };
const S = Math.SQRT1_2;
const PALM_IN: Record<Side, Quat> = { left: [0, 0, S, S], right: [0, 0, -S, S] }; // (x, y, z, w)
const NEUTRAL: Quat = [0, 0, 0, 1];

/** In the page: apply one set of device states to the emulated Quest, read the page. */
function applyAndObserve(command: DeviceCommand | null): Seen {
  const device: EmulatedDevice | undefined = window.__xrDevice;
  const workcell = window.__workcell;
  if (device === undefined || workcell === undefined) throw new Error("the page has no emulated Quest or no window.__workcell");
  if (command !== null) {
    if (command.headset) {
      device.position.set(...command.headset.pos);
      device.quaternion.set(...command.headset.quat);
    }
    for (const [side, hand] of Object.entries(command.hands ?? {})) {
      const controller = device.controllers[side as Side];
      if (controller === undefined) continue;
      if (hand.pos) controller.position.set(...hand.pos);
      if (hand.quat) controller.quaternion.set(...hand.quat);
      if (hand.grip !== undefined) controller.updateButtonValue("squeeze", hand.grip);
      if (hand.trigger !== undefined) controller.updateButtonValue("trigger", hand.trigger);
      if (hand.stick) controller.updateAxes("thumbstick", hand.stick[0], hand.stick[1]);
      for (const [button, value] of Object.entries(hand.buttons ?? {})) controller.updateButtonValue(button, value);
    }
  }
  return { snap: workcell.snapshot(), bodies: workcell.bodies() };
}

await runScript("xr_delivery", async ({ url, page, artifacts }) => {
  await startSession(page, url, { operatorId: "e2e-xr", query: { emulate: "quest3" }, artifacts });
  check(await page.evaluate(() => window.__xrDevice !== undefined), "the emulated Quest 3 is not installed");
  await page.waitForSelector("#hud dl");
  await checkDrawn(page, path.join(artifacts, "hud-desktop.png"), page.locator("#hud"));

  // Enter immersive VR (a click is the user gesture WebXR needs).
  await page.click("#enter-vr");
  let s = await waitFor(page, (s) => s.teleop?.presenting === true && s.teleop.xr_frames > 5, { what: "the XR session" });
  log(`in immersive-vr, view ${s.teleop?.view}`);
  const hands: Record<Side, HandCommand> = {
    left: { pos: REST.left, quat: NEUTRAL, grip: 0, trigger: 0, stick: [0, 0] },
    right: { pos: REST.right, quat: NEUTRAL, grip: 0, trigger: 0, stick: [0, 0] },
  };
  const headset: DeviceCommand["headset"] = { pos: [0, 1.6, 0], quat: [Math.sin(-0.2), 0, 0, Math.cos(-0.2)] };
  await page.evaluate(applyAndObserve, { headset, hands });

  // B toggles first/third person; toggle twice and check both views are drawn.
  await sleep(600);
  await checkDrawn(page, path.join(artifacts, "xr-first-person.png"));
  await page.evaluate(applyAndObserve, { hands: { right: { buttons: { "b-button": 1 } } } });
  await waitFor(page, (s) => s.teleop?.view === "third", { what: "B to switch to third person" });
  await page.evaluate(applyAndObserve, { hands: { right: { buttons: { "b-button": 0 } } } });
  await sleep(600);
  await checkDrawn(page, path.join(artifacts, "xr-third-person.png"));
  await page.evaluate(applyAndObserve, { hands: { right: { buttons: { "b-button": 1 } } } });
  await waitFor(page, (s) => s.teleop?.view === "first", { what: "B to switch back to first person" });
  await page.evaluate(applyAndObserve, { hands: { right: { buttons: { "b-button": 0 } } } });

  // The HUD panel is parked off the forward view while the hands rest or work; a left
  // thumbstick press hides it and another brings it back.
  s = await waitFor(page, (s) => s.teleop?.hud.where === "parked", { what: "the HUD parked off the view" });
  const hudAngle = s.teleop?.hud.off_axis_deg ?? 0;
  log(`XR HUD parked ${hudAngle.toFixed(1)} degrees off the robot's forward view`);
  check(hudAngle > 45 && s.teleop?.hud.visible === true, `the XR HUD is ${hudAngle.toFixed(1)} degrees off the view (wanted > 45)`);
  for (const mode of ["hidden", "wrist"] as const) {
    await page.evaluate(applyAndObserve, { hands: { left: { buttons: { thumbstick: 1 } } } });
    await waitFor(page, (s) => s.teleop?.hud.mode === mode, { what: `the left thumbstick press to make the HUD ${mode}` });
    await page.evaluate(applyAndObserve, { hands: { left: { buttons: { thumbstick: 0 } } } });
  }
  s = await waitFor(page, (s) => s.teleop?.hud.visible === true, { what: "the HUD to show again" });
  check(s.teleop?.comfort.vignette === 0, "the vignette is on while the base stands still");

  // The trial clock runs once the countdown is over; the HUD panel in the headset shows it.
  s = await waitFor(page, (s) => s.hud?.phase === "running", { what: "the countdown to end" });
  await sleep(300);
  const panel = await page.evaluate(() => window.__workcell?.capture("hud_panel") ?? null);
  check(panel !== null && panel.startsWith("data:image/png"), "no XR HUD panel");
  writeFileSync(path.join(artifacts, "xr-hud-panel.png"), Buffer.from(panel.split(",")[1] ?? "", "base64"));
  const panelStats = await imageStats(page, panel);
  log(`XR HUD panel: luminance variance ${panelStats.variance.toFixed(1)}, ${panelStats.colours} colours`);
  check(panelStats.variance > 100, "the XR HUD panel is blank");
  const start = s.state;
  const operator = new ScriptedOperator();
  const ctrl: Record<Side, Vec3> = { left: [...REST.left], right: [...REST.right] };
  let inputsWithPose = 0;
  let command: DeviceCommand | null = null;
  const act = async (decision: Decision, obs: Observation, snap: DebugSnapshot): Promise<number> => {
    const corrections = controllerCorrections(obs, decision.targets);
    if (!decision.grip) {
      ctrl.left = [...REST.left];
      ctrl.right = [...REST.right];
    }
    (["left", "right"] as const).forEach((side, i) => {
      const c = corrections[i];
      if (c) ctrl[side] = [ctrl[side][0] + c[0], ctrl[side][1] + c[1], ctrl[side][2] + c[2]];
    });
    const grip = decision.grip ? 1 : 0;
    const trigger = decision.trigger ? 1 : 0;
    // Applied on the next look: one round trip per tick.
    command = {
      hands: {
        left: {
          pos: ctrl.left,
          quat: decision.palmsIn ? PALM_IN.left : NEUTRAL,
          grip,
          trigger,
          // xr-standard thumbstick: x right, y down
          stick: [-decision.drive.left, -decision.drive.forward],
        },
        right: {
          pos: ctrl.right,
          quat: decision.palmsIn ? PALM_IN.right : NEUTRAL,
          grip,
          trigger,
          stick: [decision.drive.turn, 0],
        },
      },
    };
    const sent = snap.teleop?.last_input;
    if (sent?.source === "xr" && sent.left.pose !== null && sent.right.pose !== null) inputsWithPose += 1;
    return 0;
  };
  const run = await deliver(page, artifacts, operator, {
    prefix: "xr",
    tickMs: TICK_MS,
    debugEveryMs: 1000,
    adaptLead: true,
    look: () => page.evaluate(applyAndObserve, command),
    act,
    debug: (decision, obs, snap) => {
      const box = obs.boxes.find((b) => b.name === operator.box);
      const sent = snap.teleop?.last_input;
      return `drive=${JSON.stringify(decision.drive)} box=${box?.pos.map((v) => v.toFixed(3))} holding=${obs.holding} following=${obs.following} input=${JSON.stringify(sent?.left.stick)} seq=${sent?.seq} applied=${snap.state?.input_seq}`;
    },
  });
  await checkDrawn(page, path.join(artifacts, "xr-end.png"));
  // Driving in first person narrowed the view; standing still it is clear again.
  const still = await waitFor(page, (s) => s.teleop?.comfort.vignette === 0, { what: "the vignette to clear" });
  const peak = still.teleop?.comfort.vignette_peak ?? 0;
  log(`tunnel vignette: peak ${peak.toFixed(2)} while driving, ${still.teleop?.comfort.vignette} standing still`);
  check(peak > 0.3, `the tunnel vignette peaked at ${peak.toFixed(2)} while the base drove (wanted > 0.3)`);

  // Leave VR: the desktop end-of-campaign screen and the HUD are drawn.
  await page.evaluate(() => document.querySelector<HTMLButtonElement>("#enter-vr")?.click());
  await waitFor(page, (s) => s.teleop?.presenting === false, { what: "the XR session to end" });
  await page.waitForSelector("#end-screen.campaign-end");
  await checkDrawn(page, path.join(artifacts, "end-screen.png"), page.locator("#end-screen"));
  await checkDrawn(page, path.join(artifacts, "view-after.png"));

  const result = {
    ...deliveryResult(run),
    xr_inputs_with_pose: inputsWithPose,
    input_seq_applied: start?.input_seq ?? null,
    stale_states_dropped: run.end.stats.stale,
    hud_off_axis_deg: hudAngle,
    vignette_peak: peak,
  };
  console.log(`RESULT ${JSON.stringify(result)}`);
  checkDelivered(run, "thumbstick");
});
