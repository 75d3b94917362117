// The sort task on the desktop page, keyboard only: pick "sort" on the setup page, wait for
// the first box to come to rest at the end of the belt, drive the robot up to it, take
// both grips, bring the hands together and lower them onto the box until the HUD's stage
// says a gripper touched it: the task's first stage (touch_by_keys.ts drives). Prints
// "RESULT {json}" for the pytest wrapper (tests/web/test_sort_browser.py).
//
//   npm run build:e2e && node build/e2e/tests/e2e/sort_desktop.js http://127.0.0.1:8000   (in web/)

import type { Pose } from "../../src/protocol";
import { runScript } from "./lib.js";
import { standAtBeltEnd } from "./approach.js";
import { touchByKeys, touchedResult } from "./touch_by_keys.js";

const BELT_END_X = -0.5; // a box past this x has reached the end of the belt
const RESTING_M = 0.003; // ...and rests once it stays within this of where it was seen...
const REST_S = 0.4; // ...for this long (trial time: a loaded page may answer two looks from one state)

await runScript("sort_desktop", async ({ url, page, artifacts }) => {
  let seen: { pose: Pose; t: number } | null = null;
  const run = await touchByKeys(page, url, artifacts, {
    task: "sort",
    operatorId: "e2e-sort",
    boxToReach: (bodies, t) => {
      const first = bodies["box_0"] ?? null; // the first box the feeder releases
      if (first === null || first[0] <= BELT_END_X) {
        seen = null;
        return null;
      }
      if (seen === null || Math.hypot(first[0] - seen.pose[0], first[1] - seen.pose[1]) >= RESTING_M) {
        seen = { pose: first, t };
        return null;
      }
      return t - seen.t >= REST_S ? first : null;
    },
    standFor: standAtBeltEnd,
  });
  console.log(`RESULT ${JSON.stringify(touchedResult(run))}`);
});
