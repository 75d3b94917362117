// The shelve task on the desktop page, keyboard only: pick "shelve" on the setup page, then
// drive the robot up to the box waiting on the table, take both grips, bring the hands
// together and lower them onto the box until the HUD's stage says a gripper touched it:
// the task's first stage (touch_by_keys.ts drives). The HUD names the shelf the trial
// asks for. Prints "RESULT {json}" for the pytest wrapper (tests/web/test_shelve_browser.py).
//
//   npm run build:e2e && node build/e2e/tests/e2e/shelve_desktop.js http://127.0.0.1:8000   (in web/)

import { check, runScript } from "./lib.js";
import { standAtTable } from "./approach.js";
import { touchByKeys, touchedResult } from "./touch_by_keys.js";

await runScript("shelve_desktop", async ({ url, page, artifacts }) => {
  const run = await touchByKeys(page, url, artifacts, {
    task: "shelve",
    operatorId: "e2e-shelve",
    boxToReach: (bodies) => bodies["box_0"] ?? null, // it waits on the table from the start
    standFor: standAtTable,
  });
  // the HUD says what the trial asks (which shelf), above its lines
  const shown = (await page.locator("#hud .hud-instruction").textContent()) ?? "";
  const asked = run.last.hud?.instruction;
  check(shown === asked, `the HUD shows "${shown}", the trial asks "${asked}"`);
  console.log(`RESULT ${JSON.stringify({ ...touchedResult(run), hud_instruction: shown })}`);
});
