// End to end: a study participant pauses, is asked to confirm a stop, stops with a reason,
// and resumes their plan's step from the end screen. They accept the consent and start
// (their plan: one collection session of three short trials); once the first trial has
// timed out they press P (the trial's clock and the robot stand still: the overlay says
// "Paused"), open Stop and cancel it, resume with the overlay's button, pause again, and
// stop with a reason typed into the confirmation. The end screen says who stopped and why,
// and offers "Resume this session" (one of its trials done); choosing it starts a session
// that goes on with the second trial. Once that trial has ended, the admin stops the session
// from the admin page (confirmed, with a reason): the participant's end screen says the
// administrator stopped it and why, and offers to resume again (two trials done); the third
// session runs the last trial and completes; the end screen then thanks them.
//
//   npm run build:e2e && node build/e2e/tests/e2e/study_control.js <server url> <participant token> <admin token>

import path from "node:path";
import { check, log, pageUrl, runScript, screenshotStats, sleep, waitFor } from "./lib.js";

const [, , , participantToken, adminToken] = process.argv;
const REASON = "I need a short break";
const ADMIN_REASON = "the lab closes in five minutes";

await runScript("study_control", async ({ url, page, context, artifacts }) => {
  check(participantToken !== undefined && adminToken !== undefined, "usage: study_control.js URL PARTICIPANT_TOKEN ADMIN_TOKEN");
  await page.goto(pageUrl(url, { token: participantToken, quality: "low" }));
  await waitFor(page, (s) => s.link.status === "open" && s.role === "operator", { what: "the link to open as operator" });
  await page.waitForSelector(".study-page .study-next");
  await page.check(".study-consent-box");
  await page.click("button.start");
  const started = await waitFor(page, (s) => s.session_active && s.page === "#/teleop", { what: "the planned session to start" });
  const first = started.session_id;
  await waitFor(page, (s) => s.events.some((e) => e.kind === "trial_started" && e.trial_index === 1) && s.hud?.phase === "running", {
    what: "the first trial to time out and the second to run",
  });

  // Pause with the key: the overlay says so and the trial's clock stands still.
  await page.keyboard.press("KeyP");
  let s = await waitFor(page, (s) => s.teleop?.paused === true, { what: "P to pause the trial" });
  await page.waitForSelector("#end-screen.paused #resume-session");
  await sleep(400); // the last State before the pause may still arrive
  const clock = (await waitFor(page, (s) => s.state !== null, { what: "a state" })).state?.t_sim ?? 0;
  await sleep(1500);
  s = await waitFor(page, (s) => s.state !== null, { what: "a state" });
  check(s.state?.t_sim === clock, `the trial's clock moved while paused: ${clock} -> ${String(s.state?.t_sim)}`);
  check((await page.textContent("#pause-session")) === "Resume", "the toolbar's pause button does not offer Resume");
  await screenshotStats(page, path.join(artifacts, "paused.png"));
  log(`paused at t_sim ${clock.toFixed(2)} s; the clock stood still for 1.5 s`);

  // Stop asks first; "Keep going" keeps the session.
  await page.click("#stop-session");
  await page.waitForSelector("#stop-dialog #stop-reason");
  const question = (await page.textContent("#stop-dialog")) ?? "";
  check(question.includes("goes on from this trial"), `the stop question reads: ${question}`);
  await screenshotStats(page, path.join(artifacts, "stop-dialog.png"));
  await page.click("#stop-cancel");
  check((await page.$("#stop-dialog")) === null, "the dialog stayed open after Keep going");
  await sleep(300);
  s = await waitFor(page, (s) => s.session_active, { what: "the session to keep running" });
  check(s.ended === null, "cancelling the stop ended the session");

  // Resume with the overlay's button, then pause again and stop with a reason.
  await page.click("#resume-session");
  await waitFor(page, (s) => s.teleop?.paused === false, { what: "Resume to resume the trial" });
  await page.waitForSelector("#end-screen.hidden", { state: "attached" });
  await page.click("#pause-session");
  await waitFor(page, (s) => s.teleop?.paused === true, { what: "the toolbar's Pause to pause again" });
  await page.click("#stop-session");
  await page.fill("#stop-reason", REASON);
  await page.click("#stop-confirm");
  const stopped = await waitFor(page, (s) => s.ended !== null, { what: "the confirmed stop to end the session" });
  check(stopped.ended?.reason === "operator_stop", `the session ended ${String(stopped.ended?.reason)}`);
  check(stopped.ended?.stop_note === REASON, `the stop's reason came back as ${String(stopped.ended?.stop_note)}`);

  // The end screen: who stopped and why, in words, and the plan's step to resume.
  await page.waitForSelector("#end-screen #next-step");
  const screen = (await page.textContent("#end-screen")) ?? "";
  check(screen.includes(`You stopped the session: ${REASON}`), `the end screen reads: ${screen}`);
  check(!screen.includes("operator_stop") && !screen.includes("New session"), `the end screen reads: ${screen}`);
  const step = (await page.textContent("#end-screen .study-next-step")) ?? "";
  check(step.includes("1 of its trials are done") && step.includes("trial 2"), `the next step reads: ${step}`);
  check((await page.textContent("#next-step")) === "Resume this session", "the end screen does not offer to resume");
  await screenshotStats(page, path.join(artifacts, "stopped.png"));
  log(`end screen: ${step}`);

  await page.click("#next-step");
  const resumed = await waitFor(page, (s) => s.session_active && s.session_id !== first, { what: "the resumed session to start" });
  const second = resumed.session_id;
  await waitFor(page, (s) => s.events.some((e) => e.kind === "trial_started" && e.trial_index === 2), {
    what: "the resumed session's first trial (the plan's second) to end",
  });
  const begun = (await waitFor(page, (s) => s.session_active, { what: "the session" })).events
    .filter((e) => e.kind === "trial_started")
    .map((e) => e.trial_index);
  check(!begun.includes(0), `the resumed session began the trials ${begun.join(", ")}`);

  // The admin stops it from the admin page: confirmed, with a reason the participant reads.
  const admin = await context.newPage();
  await admin.setViewportSize({ width: 1100, height: 600 });
  await admin.goto(pageUrl(url, { token: adminToken, role: "spectator" }, "#/admin"));
  await admin.click('.participants tr[data-participant="p01"].state-running button.stop-session');
  await admin.waitForSelector("#stop-dialog #stop-reason");
  await admin.fill("#stop-reason", ADMIN_REASON);
  await screenshotStats(admin, path.join(artifacts, "admin-stop.png"));
  await admin.click("#stop-confirm");
  const byAdmin = await waitFor(page, (s) => s.ended !== null && s.ended.session_id === second, { what: "the admin's stop" });
  check(byAdmin.ended?.reason === "admin_stop" && byAdmin.ended.stop_note === ADMIN_REASON, `ended ${JSON.stringify(byAdmin.ended)}`);
  await page.waitForSelector("#end-screen #next-step");
  const told = (await page.textContent("#end-screen")) ?? "";
  check(told.includes(`The study's administrator stopped the session: ${ADMIN_REASON}`), `the end screen reads: ${told}`);
  const again = (await page.textContent("#end-screen .study-next-step")) ?? "";
  check(again.includes("2 of its trials are done") && again.includes("trial 3"), `the next step reads: ${again}`);
  await admin.close();

  await page.click("#next-step");
  const last = await waitFor(page, (s) => s.session_active && s.session_id !== second, { what: "the last session to start" });
  const third = last.session_id;
  const done = await waitFor(page, (s) => s.ended !== null && s.ended.session_id === third, {
    what: "the last session to complete",
    timeout: 120000,
  });
  check(done.ended?.reason === "completed", `the last session ended ${String(done.ended?.reason)}`);
  await page.waitForSelector("#end-screen .study-next-step");
  const thanks = (await page.textContent("#end-screen .study-next-step")) ?? "";
  check(thanks.includes("every session of this study"), `after the last step the end screen reads: ${thanks}`);
  await screenshotStats(page, path.join(artifacts, "finished.png"));
  console.log(`RESULT ${JSON.stringify({ first, second, third, paused_at: clock })}`);
});
