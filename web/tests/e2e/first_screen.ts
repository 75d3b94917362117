// End to end (issue 36, point 9): the operator's first screen is a few choices (task, mode,
// grasp, name) with Start in view without scrolling and every other setting folded under
// "Advanced"; the mode is chosen once (its buttons; no second field). In the session the
// HUD's score is the points earned so far (0 with nothing delivered, the score the trial's
// end then gives) with the time bonus of a success apart; the key map is open the first
// time, folded the next, and the Keys button's choice is remembered.
//
//   npm run build:e2e && node build/e2e/tests/e2e/first_screen.js http://127.0.0.1:8000   (in web/)

import path from "node:path";
import { check, log, pageUrl, runScript, screenshotStats, waitFor } from "./lib.js";

await runScript("first_screen", async ({ url, page, artifacts }) => {
  await page.setViewportSize({ width: 1280, height: 720 });
  await page.goto(pageUrl(url, { quality: "low" }));
  await waitFor(page, (s) => s.link.status === "open" && s.role === "operator", { what: "the link to open as operator" });
  await page.waitForSelector(".setup-form .top-choices");
  await screenshotStats(page, path.join(artifacts, "first-screen.png"));

  // A few choices, then Start, all in view.
  const visible = await page.$$eval(".setup-form .field", (rows) =>
    rows.filter((r) => (r as HTMLElement).checkVisibility()).map((r) => (r as HTMLElement).dataset["field"] ?? ""),
  );
  check(JSON.stringify(visible) === JSON.stringify(["task.kind", "world.grasp", "operator_id"]), `the first screen shows the fields ${visible.join(", ")}`);
  const tasks = await page.$$eval('select[name="task.kind"] option', (options) => options.map((o) => (o as HTMLOptionElement).value));
  check(tasks.includes("box_transfer"), `the task choices are ${tasks.join(", ")}`);
  const modes = await page.$$eval(".mode-choice", (buttons) => buttons.map((b) => (b as HTMLElement).dataset["mode"] ?? ""));
  check(modes.join(",") === "practice,collection,challenge", `the mode buttons are ${modes.join(", ")}`);
  check(!(await page.isVisible('select[name="task.mode"]')), "the mode is offered a second time as a field");
  const start = await page.locator("button.start").boundingBox();
  check(start !== null && start.y + start.height <= 720, `Start is below the fold (${JSON.stringify(start)})`);
  check(!(await page.getAttribute("details.advanced", "open")), "Advanced is open at first");
  const hidden = await page.$$eval("details.advanced .field", (rows) => rows.length);
  check(hidden >= 30, `only ${hidden} settings under Advanced`);
  log(`first screen: ${visible.join(", ")} + mode buttons; Start at y=${start.y.toFixed(0)}; ${hidden} settings under Advanced`);

  // A setting under Advanced that the server refuses opens Advanced beside its problem.
  await page.click("details.advanced > summary");
  await page.fill('input[name="task.time_limit_s"]', "-5");
  await page.click("details.advanced > summary"); // folded again before Start
  await page.click("button.start");
  await page.waitForSelector('.field.invalid[data-field="task.time_limit_s"] .problem:not(:empty)');
  check((await page.getAttribute("details.advanced", "open")) !== null, "Advanced stayed folded over a refused setting");

  // A practice trial of 4 s with nothing delivered.
  await page.fill('input[name="task.time_limit_s"]', "4");
  await page.fill('input[name="task.countdown_s"]', "0");
  await page.click('.mode-choice[data-mode="practice"]');
  await page.selectOption('select[name="world.grasp"]', "assisted");
  await page.fill('input[name="operator_id"]', "e2e-first");
  await page.click("button.start");
  const running = await waitFor(page, (s) => s.page === "#/teleop" && s.hud?.phase === "running", { what: "the trial to run" });
  check(running.session?.settings["world"] !== undefined, "the session has no settings");
  const hudText = (await page.textContent("#hud")) ?? "";
  log(`HUD: ${hudText}`);
  check(/Score\s*0(?!\d)/.test(hudText), `with nothing delivered the HUD's score reads: ${hudText}`);
  check(/Time bonus\s*\+[1-4] on success/.test(hudText), `the HUD shows no time bonus apart: ${hudText}`);
  check(await page.isVisible("#keymap"), "the key map is folded on first use");
  const ended = await waitFor(page, (s) => s.last_trial_end !== null, { what: "the trial to end" });
  const end = ended.last_trial_end;
  check(end !== null && end.outcome === "timeout" && end.score === 0, `the trial ended ${JSON.stringify(end)}`);

  // The next visit: the key map is folded; the Keys button opens it, and that is kept.
  check(page.url().endsWith("#/teleop"), `the page is at ${page.url()}`);
  await page.reload(); // a new page load, as the operator's next visit
  await waitFor(page, (s) => s.link.status === "open" && s.page === "#/teleop", { what: "the teleop page again" });
  await page.waitForSelector("#keymap", { state: "attached" });
  check(!(await page.isVisible("#keymap")), "the key map covers the view on the second visit");
  await page.click("#toggle-keys");
  check(await page.isVisible("#keymap"), "the Keys button does not open the key map");
  await page.reload();
  await page.waitForSelector("#keymap", { state: "attached" });
  await waitFor(page, (s) => s.page === "#/teleop", { what: "the teleop page after reload" });
  check(await page.isVisible("#keymap"), "the key map's chosen state was not kept");
  await page.click("#keymap .keymap-close");
  check(!(await page.isVisible("#keymap")), "Hide does not fold the key map");
  console.log(`RESULT ${JSON.stringify({ session_id: running.session_id, hud: hudText, end_score: end.score, first_screen: visible })}`);
});
