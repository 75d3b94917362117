// Hand tracking in an emulated Meta Quest 3 (IWER's hand input, Meta's recorded hand poses):
// with hands instead of controllers the page sends "xr_hands" input; a grab (middle, ring
// and little finger curled: IWER's "point" pose) engages the left arm's clutch and the arm
// follows the wrist 10 cm; a pinch closes the gripper and lets the clutch go.
// Prints "RESULT {json}" for the pytest wrapper, which checks the recorded frames.
//
//   npm run build:e2e && node build/e2e/tests/e2e/xr_hands.js http://127.0.0.1:8000   (in web/)

import path from "node:path";
import { check, checkDrawn, log, runScript, waitFor } from "./lib.js";
import { startSession, waitForEnd } from "./flow.js";

interface HandChange {
  poseId?: string;
  pinch?: number;
  forward?: number;
}

/** In the page: set the left hand's pose (IWER pose id), pinch, or move it forward (metres). */
function leftHand(change: HandChange): void {
  const hand = window.__xrDevice?.hands.left;
  if (hand === undefined) throw new Error("the page has no emulated hands");
  if (change.poseId !== undefined) hand.poseId = change.poseId;
  if (change.pinch !== undefined) hand.updatePinchValue(change.pinch);
  if (change.forward !== undefined) hand.position.z -= change.forward;
}

await runScript("xr_hands", async ({ url, page, artifacts }) => {
  await startSession(page, url, { operatorId: "e2e-xr-hands", query: { emulate: "quest3" }, artifacts });
  await page.evaluate(() => {
    const quest = window.__xrDevice;
    if (quest === undefined) throw new Error("the page has no emulated Quest");
    quest.primaryInputMode = "hand";
  });
  await page.click("#enter-vr");
  await waitFor(page, (s) => s.teleop?.presenting === true && s.teleop.xr_frames > 5, { what: "the XR session" });
  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the trial to run" });

  let s = await waitFor(page, (s) => s.teleop?.last_input?.source === "xr_hands" && s.teleop.last_input.left.pose !== null, {
    what: "hand-tracked input with a wrist pose",
  });
  const open = s.teleop?.last_input?.left;
  check(open !== undefined && open.grip === 0 && open.trigger === 0, `an open hand reads as ${JSON.stringify(open)}`);

  await page.evaluate(leftHand, { poseId: "point" });
  s = await waitFor(page, (s) => (s.teleop?.last_input?.left.grip ?? 0) > 0.9 && s.state?.following[0] === true, {
    what: "a grab to engage the left arm",
  });
  const before = s.state?.tcp_targets[0] ?? null;
  check(before !== null, "no TCP target in the state");
  const shift = (snap: typeof s): number => {
    const now = snap.state?.tcp_targets[0];
    return now === undefined ? 0 : Math.hypot(now[0] - before[0], now[1] - before[1], now[2] - before[2]);
  };
  await page.evaluate(leftHand, { forward: 0.1 });
  s = await waitFor(page, (s) => shift(s) > 0.08, { what: "the left arm's target to follow the wrist 10 cm" });
  const moved = shift(s);
  log(`the grabbed hand moved the left TCP target ${(moved * 100).toFixed(1)} cm`);
  await checkDrawn(page, path.join(artifacts, "xr-hands.png"));

  await page.evaluate(leftHand, { poseId: "default", pinch: 1 });
  s = await waitFor(page, (s) => (s.teleop?.last_input?.left.trigger ?? 0) > 0.9 && s.state?.following[0] === false, {
    what: "a pinch to close the gripper and let the clutch go",
  });
  log(`pinch: ${JSON.stringify(s.teleop?.last_input?.left)}`);

  await page.evaluate(() => document.querySelector<HTMLButtonElement>("#enter-vr")?.click());
  await waitFor(page, (s) => s.teleop?.presenting === false, { what: "the XR session to end" });
  await page.click("#stop-session");
  await page.click("#stop-confirm"); // the confirmation, with no reason given
  const ended = await waitForEnd(page, 20000);
  console.log(`RESULT ${JSON.stringify({ session_id: ended.session_id ?? s.session_id, moved })}`);
});
