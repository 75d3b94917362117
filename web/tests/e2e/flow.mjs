// Steps the scripts share: open the setup page, check it, start a session with
// test-friendly settings typed into the form, and the end-of-session checks.

import path from "node:path";
import { check, log, pageUrl, screenshotStats, waitFor } from "./lib.mjs";

/** Settings the tests type into the setup form (a faster belt shortens the wait). */
export const TEST_SETTINGS = {
  operator_id: null, // set per script
  "world.conveyor.speed": "0.5",
  "task.countdown_s": "2",
};

export async function startSession(page, url, { operatorId, query = {}, artifacts, mode = "practice" }) {
  await page.goto(pageUrl(url, query));
  await waitFor(page, (s) => s.link.status === "open" && s.role === "operator" && s.scene_bodies > 0, {
    what: "the link to open as operator",
  });
  await page.waitForSelector(".setup-form");
  // Every parameter of /api/defaults is on the page with its default and documentation.
  const fields = await page.$$eval(".setup-form .field", (rows) => rows.map((r) => r.dataset.field));
  check(fields.length >= 30, `setup page shows only ${fields.length} settings`);
  check(fields.includes("task.mode") && fields.includes("world.robot.max_linear_speed"), "setup page misses settings");

  // Each setting shows what its declaration allows, and once the hints are in
  // (GET /api/settings/hints) a number typed outside those bounds is marked before the
  // server is asked.
  const doc = await page.textContent('.field[data-field="world.conveyor.speed"] .doc');
  check(doc.includes("(between 0.01 and 1 m/s)"), `conveyor speed documentation reads ${doc}`);
  await page.waitForSelector('.field[data-unit="s"] input[name="task.time_limit_s"][title]', { timeout: 10000 });

  // A bad value is rejected by the server and shown beside its field.
  await page.fill('input[name="task.time_limit_s"]', "-5");
  check(
    (await page.$('.field.invalid[data-field="task.time_limit_s"]')) !== null,
    "a negative time limit is not marked while typing",
  );
  await page.click("button.start");
  await page.waitForSelector('.field.invalid[data-field="task.time_limit_s"] .problem:not(:empty)', { timeout: 10000 });
  const problem = await page.textContent('.field[data-field="task.time_limit_s"] .problem');
  log(`config rejected beside its field: ${problem}`);
  await page.fill('input[name="task.time_limit_s"]', "120");

  await page.click(`.mode-choice[data-mode="${mode}"]`);
  await page.fill('input[name="operator_id"]', operatorId);
  for (const [key, value] of Object.entries(TEST_SETTINGS)) {
    if (value !== null) await page.fill(`[name="${key}"]`, value);
  }
  if (artifacts) await screenshotStats(page, path.join(artifacts, "setup.png"));
  await page.click("button.start");
  const s = await waitFor(page, (s) => s.session_active && s.page === "#/teleop" && s.state !== null, {
    what: "the session to start and the teleop page to show",
    timeout: 20000,
  });
  log(`session ${s.session_id} started`);
  return s;
}

/** Wait for the trial's end and the session's; returns the last snapshot. */
export async function waitForEnd(page, timeout) {
  return waitFor(page, (s) => s.ended !== null, { what: "the session to end", timeout, every: 250 });
}

export async function checkDrawn(page, file, locator = null, minVariance = 50) {
  const stats = await screenshotStats(page, file, locator);
  check(stats.variance > minVariance && stats.colours > 20, `${path.basename(file)} looks blank (variance ${stats.variance.toFixed(1)}, ${stats.colours} colours)`);
  return stats;
}
