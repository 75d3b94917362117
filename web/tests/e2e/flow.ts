// Steps the scripts share: open the setup page, check it, start a session with
// test-friendly settings typed into the form, and wait for the session's end.

import path from "node:path";
import type { Page } from "playwright-core";
import { PATIENCE_MS, check, log, pageUrl, screenshotStats, waitFor } from "./lib.js";
import type { DebugSnapshot } from "./lib.js";

/** Settings the tests type into the setup form (a faster belt shortens the wait). */
export const TEST_SETTINGS: Record<string, string> = {
  "world.conveyor.speed": "0.5",
  "task.countdown_s": "2",
};

export interface StartOptions {
  operatorId: string;
  query?: Record<string, string>;
  artifacts?: string;
  mode?: "practice" | "collection" | "challenge";
  task?: string;
  /** Further settings typed into the form (by their dotted names), after the tests' own. */
  settings?: Record<string, string>;
}

export async function startSession(
  page: Page,
  url: string,
  { operatorId, query = {}, artifacts, mode = "practice", task = "box_transfer", settings = {} }: StartOptions,
): Promise<DebugSnapshot> {
  await page.goto(pageUrl(url, query));
  await waitFor(page, (s) => s.link.status === "open" && s.role === "operator" && s.scene_bodies > 0, {
    what: "the link to open as operator",
  });
  await page.waitForSelector(".setup-form");
  // Every parameter of /api/defaults is on the page with its default and documentation.
  const fields = await page.$$eval(".setup-form .field", (rows) => rows.map((r) => (r as HTMLElement).dataset["field"] ?? ""));
  check(fields.length >= 30, `setup page shows only ${fields.length} settings`);
  check(fields.includes("task.mode") && fields.includes("world.robot.max_linear_speed"), "setup page misses settings");
  // The tasks are offered first, as a choice of every built-in task.
  const tasks = await page.$$eval('.top-choices select[name="task.kind"] option', (options) =>
    options.map((o) => (o as HTMLOptionElement).value),
  );
  check(tasks.includes(task), `the setup page offers the tasks ${tasks.join(", ")}, not ${task}`);
  await page.selectOption('select[name="task.kind"]', task);
  // The first screen is a few choices and Start; every other setting is folded under
  // "Advanced", opened here to type the test's settings.
  check(!(await page.isVisible('input[name="task.time_limit_s"]')), "the advanced settings are not folded");
  await page.click("details.advanced > summary");

  // Each setting shows what its declaration allows, and once the hints are in
  // (GET /api/settings/hints) a number typed outside those bounds is marked before the
  // server is asked.
  const doc = (await page.textContent('.field[data-field="world.conveyor.speed"] .doc')) ?? "";
  check(doc.includes("(between 0.01 and 1 m/s)"), `conveyor speed documentation reads ${doc}`);
  await page.waitForSelector('.field[data-unit="s"] input[name="task.time_limit_s"][title]', { timeout: PATIENCE_MS });

  // A bad value is rejected by the server and shown beside its field (by its path).
  await page.fill('input[name="task.time_limit_s"]', "-5");
  check(
    (await page.$('.field.invalid[data-field="task.time_limit_s"]')) !== null,
    "a negative time limit is not marked while typing",
  );
  await page.click("button.start");
  await page.waitForSelector('.field.invalid[data-field="task.time_limit_s"] .problem:not(:empty)', { timeout: PATIENCE_MS });
  const problem = await page.textContent('.field[data-field="task.time_limit_s"] .problem');
  log(`config rejected beside its field: ${problem}`);
  check(problem?.startsWith("task.time_limit_s = -5") === true, `the problem beside task.time_limit_s reads: ${problem}`);
  await page.fill('input[name="task.time_limit_s"]', "120");

  await page.click(`.mode-choice[data-mode="${mode}"]`);
  await page.fill('input[name="operator_id"]', operatorId);
  for (const [key, value] of Object.entries({ ...TEST_SETTINGS, ...settings })) await page.fill(`[name="${key}"]`, value);
  if (artifacts !== undefined) await screenshotStats(page, path.join(artifacts, "setup.png"));
  await page.click("button.start");
  const s = await waitFor(page, (s) => s.session_active && s.page === "#/teleop" && s.state !== null, {
    what: "the session to start and the teleop page to show",
  });
  log(`session ${s.session_id} started`);
  return s;
}

/** A snapshot whose session has ended (and so has its last trial). */
export type EndedSnapshot = DebugSnapshot & { ended: NonNullable<DebugSnapshot["ended"]> };

/** Wait for the session's end; returns the last snapshot. */
export async function waitForEnd(page: Page, timeout: number): Promise<EndedSnapshot> {
  const s = await waitFor(page, (s) => s.ended !== null, { what: "the session to end", timeout, every: 250 });
  const ended = s.ended;
  check(ended !== null, "the session did not end");
  return { ...s, ended };
}
