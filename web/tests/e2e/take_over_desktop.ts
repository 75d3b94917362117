// A person corrects the scripted expert from the desktop page (issue 35): a practice
// session with driver "expert" starts from the setup page; the person watches, presses T
// to take over (the HUD says they drive), holds G and R to raise the left arm, presses T
// again to hand back, and the expert goes on and delivers the box. Prints "RESULT {json}"
// with the session, the HUD's driver lines and how far the left arm's target rose.
//
// A second argument names another driver (policy:PATH): the session then runs 20 s and the
// policy drives on to the end after the hand-back, delivering or not.
//
//   npm run build:e2e && node build/e2e/tests/e2e/take_over_desktop.js http://127.0.0.1:8000 [DRIVER]   (in web/)

import { check, log, runScript, sleep, waitFor } from "./lib.js";
import { startSession, waitForEnd } from "./flow.js";

const RAISE_MS = 1500;

const driver = process.argv[3] ?? "expert";
const expert = driver === "expert";
const settings: Record<string, string> = expert ? { driver } : { driver, "task.time_limit_s": "20" };

await runScript("take_over_desktop", async ({ url, page }) => {
  await startSession(page, url, {
    operatorId: "e2e-corrector",
    query: { quality: "low" },
    settings,
  });
  const view = await page.locator("canvas.viewer-canvas").boundingBox();
  check(view !== null, "no 3D view on the teleop page");
  await page.mouse.click(view.x + view.width / 2, view.y + view.height / 2); // focus the view
  const watching = await waitFor(page, (s) => s.hud?.phase === "running" && (s.state?.t_sim ?? 0) > 2, {
    what: "the expert to drive for two seconds",
  });
  const named = watching.hud?.driver ?? "";
  check((expert ? named === "expert" : named.startsWith("policy:")) && watching.hud?.taken_over === false, `the HUD reads ${JSON.stringify(watching.hud)}`);
  const hudText = async (): Promise<string> => (await page.textContent(".hud-lines")) ?? "";
  const watchingLine = await hudText();
  check(watchingLine.includes(named), `the HUD does not say ${named} drives: ${watchingLine}`);

  await page.keyboard.press("t");
  const took = await waitFor(page, (s) => s.hud?.taken_over === true, { what: "the take-over" });
  const before = took.state?.tcp_targets[0][2] ?? 0;
  await sleep(600); // the HUD is redrawn a few times a second
  const drivingLine = await hudText();
  check(drivingLine.includes(`you (took over from ${named})`), `the HUD does not say the person drives: ${drivingLine}`);
  log(`took over at t=${took.state?.t_sim.toFixed(2)} s`);

  await page.keyboard.down("g");
  await sleep(200);
  await page.keyboard.down("r");
  await sleep(RAISE_MS);
  await page.keyboard.up("r");
  const raised = await waitFor(page, (s) => s.state !== null, { what: "a state" });
  const after = raised.state?.tcp_targets[0][2] ?? 0;
  await page.keyboard.up("g");
  log(`left target z ${before.toFixed(3)} -> ${after.toFixed(3)} m`);

  await page.keyboard.press("t");
  await waitFor(page, (s) => s.hud?.taken_over === false, { what: "the hand-back" });
  const end = await waitForEnd(page, 200000);
  const result = {
    session_id: end.ended.session_id,
    successes: end.ended.successes,
    reason: end.ended.reason,
    driver: named,
    raised_m: Number((after - before).toFixed(3)),
    watching_line: watchingLine,
    driving_line: drivingLine,
  };
  console.log(`RESULT ${JSON.stringify(result)}`);
  if (expert) check(end.ended.successes === 1, `the expert did not deliver after the hand-back: ${JSON.stringify(end.ended)}`);
  else check(end.ended.reason === "completed", `the policy's session ended ${JSON.stringify(end.ended)}`);
});
