// `npm run test:e2e -- <server url>` (in web/, which compiles the scripts first): every end-to-end script, one after another, against a
// running `workcell serve` (default http://127.0.0.1:8000). Exits non-zero if any fails.

import { spawnSync } from "node:child_process";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const url = process.argv[2] ?? process.env.WORKCELL_URL ?? "http://127.0.0.1:8000";
const scripts = ["xr_delivery", "xr_task", "xr_shelve", "desktop_delivery", "sessions_replay", "xr_exit_toolbar", "xr_menu", "xr_hands", "first_screen", "take_over_desktop", "xr_take_over"];
let failed = 0;
for (const name of scripts) {
  console.log(`--- ${name}`);
  const run = spawnSync(process.execPath, [path.join(here, `${name}.js`), url], { stdio: "inherit" });
  if (run.status !== 0) failed += 1;
}
console.log(failed === 0 ? `all ${scripts.length} passed` : `${failed} of ${scripts.length} failed`);
process.exit(failed === 0 ? 0 : 1);
