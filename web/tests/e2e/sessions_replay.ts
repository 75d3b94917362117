// End to end: a challenge session's HUD shows round and level; a (fake, standard-mapping)
// gamepad drives the base through the Gamepad API; a dropped link reconnects by itself
// and takes control back with the resume token; Stop ends the campaign (end screen); the
// sessions page lists the trial with its outcome, and its replay plays, pauses and
// scrubs in the 3D view.
//
//   npm run build:e2e && node build/e2e/tests/e2e/sessions_replay.js http://127.0.0.1:8000   (in web/)

import path from "node:path";
import { PATIENCE_MS, check, checkDrawn, log, pageUrl, runScript, sleep, snapshot, waitFor } from "./lib.js";
import type { DebugSnapshot } from "./lib.js";
import { startSession, waitForEnd } from "./flow.js";

/** The fake pad's state, which the test sets from outside the page. */
interface FakePad {
  id: string;
  index: number;
  connected: boolean;
  mapping: "standard";
  timestamp: number;
  axes: number[];
  buttons: { pressed: boolean; touched: boolean; value: number }[];
}

declare global {
  interface Window {
    __fakePad?: FakePad;
  }
}

/** The page's state now (it runs: `window.__workcell` is installed). */
async function now(page: Parameters<typeof snapshot>[0]): Promise<DebugSnapshot> {
  const s = await snapshot(page);
  check(s !== null, "the page has no window.__workcell");
  return s;
}

/** Before the page loads: one standard gamepad whose state the test sets. */
function fakeGamepad(): void {
  const pad: FakePad = {
    id: "e2e standard gamepad",
    index: 0,
    connected: true,
    mapping: "standard",
    timestamp: 0,
    axes: [0, 0, 0, 0],
    buttons: Array.from({ length: 17 }, () => ({ pressed: false, touched: false, value: 0 })),
  };
  window.__fakePad = pad;
  navigator.getGamepads = () => [pad as unknown as Gamepad, null, null, null];
}

await runScript("sessions_replay", async ({ url, page, artifacts }) => {
  await page.addInitScript(fakeGamepad);
  // Every page asks whether it is a study participant's: outside a study that is no error.
  const studyAnswers: number[] = [];
  page.on("response", (response) => {
    if (response.url().includes("/api/study/me")) studyAnswers.push(response.status());
  });
  const started = await startSession(page, url, {
    operatorId: "e2e-replay",
    query: { quality: "low" },
    mode: "challenge",
  });
  const sessionId = started.session_id;
  await waitFor(page, (s) => s.hud?.phase === "running", { what: "the trial to run" });
  const hudText = (await page.textContent("#hud")) ?? "";
  check(/Round\s*1\/5/.test(hudText) && /Level\s*1/.test(hudText), `challenge HUD reads: ${hudText}`);
  await checkDrawn(page, path.join(artifacts, "hud-challenge.png"), page.locator("#hud"));

  // Drive a little with the gamepad's left stick so the replay has motion to show.
  await page.evaluate(() => window.__fakePad?.axes.splice(1, 1, -1));
  const driving = await waitFor(page, (s) => s.teleop?.last_input?.source === "gamepad", { what: "gamepad input" });
  const stick = driving.teleop?.last_input?.left.stick;
  check(stick?.[1] === 1, `gamepad stick sent as ${JSON.stringify(stick)}`);
  await sleep(1500);
  await page.evaluate(() => window.__fakePad?.axes.splice(1, 1, 0));

  // Drop the socket: the page reconnects with backoff and resumes as the operator.
  await page.evaluate(() => window.__workcell?.dropLink());
  const dropped = await waitFor(page, (s) => s.link.status !== "open", { what: "the link to drop", every: 20 });
  log(`link ${dropped.link.status} after the drop`);
  const back = await waitFor(page, (s) => s.link.status === "open" && s.state !== null, { what: "the link to come back" });
  check(back.role === "operator", `resumed as ${back.role}, not operator`);
  check(back.session_id === sessionId && back.session_active, "the session did not survive the reconnect");
  const before = (await now(page)).teleop?.inputs_sent ?? 0;
  await sleep(800);
  const after = await now(page);
  check((after.teleop?.inputs_sent ?? 0) > before && after.errors.every((e) => e.code !== "not_allowed"), "inputs are not accepted after the reconnect");
  log("reconnected and resumed control of the same session");

  // Stop: the trial ends interrupted and the end-of-campaign screen shows.
  await page.click("#stop-session");
  await page.click("#stop-confirm"); // the confirmation, with no reason given
  const end = await waitForEnd(page, 15000);
  check(end.ended.reason === "operator_stop", `session ended by ${end.ended.reason}`);
  check(end.session?.mode === "challenge", `the session ran as ${end.session?.mode}`);
  await page.waitForSelector("#end-screen.campaign-end");
  await checkDrawn(page, path.join(artifacts, "stopped.png"));

  // The sessions page lists it, with the trial's outcome and a replay link.
  await page.click('#end-screen a[href="#/sessions"]');
  const row = page.locator(`details.session[data-session-id="${sessionId}"] tr.trial`).first();
  await row.waitFor({ timeout: PATIENCE_MS });
  const rowText = (await row.textContent()) ?? "";
  check(rowText.includes("interrupted") && rowText.includes("operator_stop") && rowText.includes("R1 L1"), `trial row reads: ${rowText}`);
  // an interrupted trial is incomplete, never included: said with the audit's reason
  check(rowText.includes("no: incomplete: interrupted (operator_stop)"), `trial row's inclusion reads: ${rowText}`);
  check(studyAnswers.length > 0 && studyAnswers.every((status) => status === 204), `/api/study/me answered ${JSON.stringify(studyAnswers)}`);
  await checkDrawn(page, path.join(artifacts, "sessions.png"));
  await row.locator("a.replay-link").click();

  // Replay: loads, plays (time advances and the robot moves), pauses, scrubs.
  const replayOf = (s: DebugSnapshot): NonNullable<DebugSnapshot["replay"]> => {
    check(s.replay !== undefined, "the replay page shows no replay state");
    return s.replay;
  };
  let replay = replayOf(await waitFor(page, (s) => s.replay?.loaded === true, { what: "the replay to load" }));
  check(replay.frames > 10, `the replay has only ${replay.frames} frames`);
  await sleep(300);
  await checkDrawn(page, path.join(artifacts, "replay-start.png"), page.locator(".viewport.replay"));
  const firstBase = replay.base;
  check(firstBase !== null, "the replay draws no robot base");
  await page.click("#replay-play");
  await waitFor(page, (s) => (s.replay?.index ?? 0) > 5, { what: "the replay to play" });
  await page.click("#replay-play");
  replay = replayOf(await now(page));
  check(!replay.playing, "pause did not pause");
  const pausedAt = replay.index;
  await sleep(400);
  check(replayOf(await now(page)).index === pausedAt, "the replay moved while paused");
  const last = replay.frames - 1;
  await page.locator("#replay-scrub").fill(String(last));
  replay = replayOf(await waitFor(page, (s) => s.replay?.index === last, { what: "the scrub bar to jump to the end" }));
  const endBase = replay.base;
  check(endBase !== null, "the replay lost the robot base");
  const moved = Math.hypot(endBase[0] - firstBase[0], endBase[1] - firstBase[1]);
  log(`replay: ${replay.frames} frames, t_end ${replay.t?.toFixed(2)} s, base moved ${moved.toFixed(2)} m`);
  check(moved > 0.1, `the replayed robot did not move (${moved.toFixed(3)} m)`);
  await checkDrawn(page, path.join(artifacts, "replay-end.png"), page.locator(".viewport.replay"));
  console.log(`RESULT ${JSON.stringify({ session_id: sessionId, replay_frames: replay.frames, replay_base_moved_m: Number(moved.toFixed(3)) })}`);

  // A reload of the setup page with no session running stays on the setup page.
  await page.goto(pageUrl(url, { quality: "low" }));
  await waitFor(page, (s) => s.link.status === "open" && s.page === "#/", { what: "the setup page after reload" });
});
