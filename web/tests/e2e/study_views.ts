// End to end (issue 36, points 7 and 8): the researcher's views of a study. While p01 runs
// their planned session, the admin page's Watch link opens it live, read-only; after it,
// the admin's Sessions link opens the Sessions page filtered to p01, with the study's
// columns, filters and downloads (the shown trials, the audit's trials.csv, the store's
// CSV export); the trial's replay names its participant, condition, study step and
// outcome, lists its events (a click goes to one), counts the frames the Sessions page
// counts and, on a renderer slowed eight times, keeps time at 1x by skipping frames.
//
//   npm run build:e2e && node build/e2e/tests/e2e/study_views.js <server url> <p01 token> <admin token>

import { readFileSync } from "node:fs";
import path from "node:path";
import type { Download, Page } from "playwright-core";
import { check, log, pageUrl, runScript, screenshotStats, sleep, waitFor } from "./lib.js";
import type { DebugSnapshot } from "./lib.js";

const [, , , participantToken, adminToken] = process.argv;

async function downloaded(page: Page, click: () => Promise<void>): Promise<{ name: string; body: Buffer }> {
  const [download] = (await Promise.all([page.waitForEvent("download"), click()])) as [Download, void];
  const file = await download.path();
  return { name: download.suggestedFilename(), body: readFileSync(file) };
}

// RFC 4180 records: a quoted cell may hold commas, doubled quotes and line breaks (the
// audit's flag_details does on a loaded machine, e.g. "sampling_gap: ..., ...").
function csvRecords(text: string): string[][] {
  const records: string[][] = [];
  let record: string[] = [];
  let cell = "";
  let quoted = false;
  for (let i = 0; i < text.length; i += 1) {
    const c = text[i];
    if (quoted) {
      if (c === '"' && text[i + 1] === '"') {
        cell += '"';
        i += 1;
      } else if (c === '"') {
        quoted = false;
      } else {
        cell += c;
      }
    } else if (c === '"') {
      quoted = true;
    } else if (c === ",") {
      record.push(cell);
      cell = "";
    } else if (c === "\n" || c === "\r") {
      if (c === "\r" && text[i + 1] === "\n") i += 1;
      record.push(cell);
      records.push(record);
      record = [];
      cell = "";
    } else {
      cell += c;
    }
  }
  if (cell !== "" || record.length > 0) records.push([...record, cell]);
  return records;
}

function csvRows(text: string): Record<string, string>[] {
  const [names = [], ...records] = csvRecords(text);
  return records.map((cells) => Object.fromEntries(cells.map((cell, i) => [names[i] ?? `${i}`, cell])));
}

await runScript("study_views", async ({ url, page, context, artifacts }) => {
  check(participantToken !== undefined && adminToken !== undefined, "usage: study_views.js URL P01_TOKEN ADMIN_TOKEN");
  await page.goto(pageUrl(url, { token: participantToken, quality: "low" }));
  await page.waitForSelector(".study-page .study-next");
  await page.check(".study-consent-box");
  await page.click("button.start");
  const started = await waitFor(page, (s) => s.session !== null && s.page === "#/teleop", { what: "p01's session to start" });
  const condition = String(started.session?.settings["condition"]);

  // The admin watches p01's running session from the admin page.
  const admin = await context.newPage();
  await admin.setViewportSize({ width: 1200, height: 700 });
  await admin.goto(pageUrl(url, { token: adminToken, role: "spectator" }, "#/admin"));
  const watch = admin.locator('.participants tr[data-participant="p01"] a.spectate-link');
  await watch.waitFor();
  const href = (await watch.getAttribute("href")) ?? "";
  check((await watch.getAttribute("target")) === "_blank", "the Watch link does not open a tab of its own");
  const [spectator] = await Promise.all([context.waitForEvent("page"), watch.click()]);
  await spectator.waitForLoadState();
  const watched = await waitFor(spectator, (s) => s.role === "spectator" && s.hud?.phase === "running" && s.session_id === started.session_id, {
    what: "the admin's tab to show p01's running session",
  });
  check(watched.page === "#/teleop", `the Watch link opened ${watched.page}`);
  await screenshotStats(spectator, path.join(artifacts, "spectating.png"));
  log(`the admin watches p01's session ${watched.session_id} (${href.replace(/token=[^&]+/, "token=…")})`);
  await spectator.close();
  await waitFor(page, (s) => s.ended !== null, { what: "p01's session to end", timeout: 120000 });

  // The admin opens p01's sessions: the Sessions page, filtered to them.
  await admin.reload();
  const sessionsLink = admin.locator('.participants tr[data-participant="p01"] a.sessions-link');
  await sessionsLink.waitFor();
  await sessionsLink.click();
  await admin.waitForSelector(`details.session[data-session-id="${started.session_id}"]`);
  check(admin.url().endsWith("#/sessions?participant=p01"), `the Sessions link opened ${admin.url()}`);
  check((await admin.inputValue("select.filter-participant")) === "p01", "the participant filter is not p01");
  const row = admin.locator("tr.trial").first();
  const cell = async (name: string): Promise<string> => (await row.locator(`td.col-${name}`).textContent()) ?? "";
  check((await cell("participant")) === "p01" && (await cell("condition")) === condition && (await cell("step")) === "1", "the study columns are wrong");
  const framesShown = Number(await cell("frames"));
  const count = (await admin.textContent(".session-count")) ?? "";
  check(count.startsWith("showing 1 of 1 sessions, 1 trials"), `the page says ${count}`);
  const other = condition === "assisted" ? "physical" : "assisted";
  await admin.selectOption("select.filter-condition", condition);
  await admin.selectOption("select.filter-trials", "interrupted");
  check((await admin.textContent(".session-list")) === "No session matches the filters.", "the outcome filter kept a timeout");
  check(admin.url().includes("trials=interrupted") && admin.url().includes(`condition=${condition}`), `the address keeps no filter: ${admin.url()}`);
  await admin.selectOption("select.filter-trials", "");
  check((await admin.$$("select.filter-condition option")).length >= 2, "the condition menu offers nothing");
  log(`sessions page filtered: ${count}; another condition would be ${other}`);
  await screenshotStats(admin, path.join(artifacts, "sessions-filtered.png"));

  // Downloads: the shown trials, the audit's trials.csv of them, the store's CSV export.
  const shown = await downloaded(admin, () => admin.click("button.download-shown"));
  const shownRows = csvRows(shown.body.toString());
  check(shownRows.length === 1 && shownRows[0]?.["operator_id"] === "p01" && shownRows[0]?.["condition"] === condition && shownRows[0]?.["study_step"] === "1", `the shown trials' CSV: ${shown.body.toString()}`);
  const audit = await downloaded(admin, () => admin.click("a.download-audit"));
  const auditRows = csvRows(audit.body.toString());
  check(audit.name === "trials.csv" && auditRows.length === 1, `the audit's download is ${audit.name} with ${auditRows.length} rows`);
  check(auditRows[0]?.["operator_id"] === "p01" && auditRows[0]?.["condition"] === condition && auditRows[0]?.["outcome"] === "timeout", `the audit's trials.csv misses the study tags or the timeout: ${JSON.stringify(auditRows[0])}`);
  const store = await downloaded(admin, () => admin.click("a.download-store"));
  check(store.name === "workcell-csv-export.zip" && store.body.subarray(0, 2).toString() === "PK", `the store download is ${store.name}`);
  const dataset = await downloaded(admin, () => admin.click("a.download-lerobot"));
  check(dataset.name === "workcell-lerobot.zip" && dataset.body.subarray(0, 2).toString() === "PK", `the dataset download is ${dataset.name}`);
  check(dataset.body.includes("workcell_selection.txt"), "the dataset does not say what it kept");
  log(`downloads: ${shown.name} (${shownRows.length} row), ${audit.name} (${auditRows.length} row), ${store.name} (${store.body.length} bytes), ${dataset.name} (${dataset.body.length} bytes)`);

  // The replay: its facts, its timeline, the frame count, and time kept at 1x.
  await row.locator("a.replay-link").click();
  const replayOf = (s: DebugSnapshot): NonNullable<DebugSnapshot["replay"]> => {
    check(s.replay !== undefined, "the replay page shows no replay state");
    return s.replay;
  };
  let replay = replayOf(await waitFor(admin, (s) => s.replay?.loaded === true, { what: "the replay to load" }));
  const fact = async (name: string): Promise<string> => (await admin.textContent(`.replay-facts dd[data-fact="${name}"]`)) ?? "";
  check((await fact("participant")) === "p01" && (await fact("condition")) === condition && (await fact("study step")) === "1", "the replay's facts miss the study tags");
  check((await fact("outcome")) === "timeout" && (await fact("boxes")) === "0/1" && (await fact("duration")).startsWith("15.0 s"), `the replay's outcome reads ${await fact("outcome")}, ${await fact("duration")}`);
  check(replay.recorded_frames === framesShown, `the replay counts ${replay.recorded_frames} frames, the Sessions page ${framesShown}`);
  const label = (await admin.textContent(".replay-clock")) ?? "";
  check(label.includes(`of ${framesShown}`), `the replay's clock reads ${label}`);
  const events = await admin.$$eval(".replay-timeline li", (items) => items.map((i) => i.textContent ?? ""));
  check(events.some((e) => e.includes("trial started")) && events.some((e) => e.includes("trial timed out")), `the timeline lists ${events.join(" | ")}`);
  await admin.locator(".replay-timeline li.event-trial_timed_out button.seek").click();
  replay = replayOf(await waitFor(admin, (s) => s.replay?.index === (s.replay?.frames ?? 0) - 1, { what: "the timeline to go to the timeout" }));
  check(replay.recorded_index === framesShown - 1 || replay.recorded_index === framesShown - 2, `the timeout is recorded frame ${replay.recorded_index}`);
  const timedOutAt = await admin.getAttribute(".replay-timeline li.event-trial_timed_out", "data-t");
  const currentAt = await admin.getAttribute(".replay-timeline li.current", "data-t");
  check(currentAt !== null && currentAt === timedOutAt, `the timeline marks the event at ${currentAt}, not the timeout's at ${timedOutAt}`);
  await screenshotStats(admin, path.join(artifacts, "replay.png"));

  // A renderer slowed eight times still plays the trial at 1x: frames are skipped instead.
  const cdp = await context.newCDPSession(admin);
  await cdp.send("Emulation.setCPUThrottlingRate", { rate: 8 });
  await admin.locator(".replay-timeline li.event-trial_started button.seek").click();
  await waitFor(admin, (s) => s.replay?.index === 0, { what: "the timeline to go to the start" });
  const startedAt = Date.now();
  await admin.click("#replay-play");
  replay = replayOf(await waitFor(admin, (s) => s.replay?.playing === false && (s.replay?.index ?? 0) > 0, { what: "the replay to play to its end", every: 250, timeout: 120000 }));
  const wall = (Date.now() - startedAt) / 1000;
  await cdp.send("Emulation.setCPUThrottlingRate", { rate: 1 });
  log(`replay at 1x on a slowed renderer: ${replay.t?.toFixed(2)} s of trial in ${wall.toFixed(2)} s of wall time, rate ${replay.rate?.toFixed(3)}, ${replay.drawn} frames drawn, ${replay.skipped} skipped`);
  check(replay.rate !== null && replay.rate > 0.85 && replay.rate < 1.1, `the replay played at ${replay.rate}x`);
  await sleep(100);
  console.log(
    `RESULT ${JSON.stringify({
      session_id: started.session_id,
      condition,
      frames: framesShown,
      replay_rate: replay.rate,
      replay_drawn: replay.drawn,
      replay_skipped: replay.skipped,
      replay_wall_s: wall,
      events: events.length,
    })}`,
  );
});
