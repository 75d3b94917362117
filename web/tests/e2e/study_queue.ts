// End to end: admission by measured headroom in the browser. With a cores budget no second
// session fits (the server runs with --admit-cores 0.01), participant p01 starts a session;
// p02's start waits in line: every page of theirs shows the queue's banner with their
// position. When p01 stops (confirmed), p02's session starts by itself and the banner goes.
//
//   npm run build:e2e && node build/e2e/tests/e2e/study_queue.js <server url> <p01 token> <p02 token>

import path from "node:path";
import type { Page } from "playwright-core";
import { check, log, pageUrl, runScript, screenshotStats, waitFor } from "./lib.js";

const [, , , firstToken, secondToken] = process.argv;

async function startAsParticipant(page: Page, url: string, token: string): Promise<void> {
  await page.goto(pageUrl(url, { token, quality: "low" }));
  await waitFor(page, (s) => s.link.status === "open" && s.role === "operator", { what: "the link to open as operator" });
  await page.waitForSelector(".study-page .study-next");
  await page.check(".study-consent-box");
  await page.click("button.start");
}

await runScript("study_queue", async ({ url, page, context, artifacts }) => {
  check(firstToken !== undefined && secondToken !== undefined, "usage: study_queue.js URL P01_TOKEN P02_TOKEN");
  await startAsParticipant(page, url, firstToken);
  const first = await waitFor(page, (s) => s.session_active && s.page === "#/teleop", { what: "p01's session to start" });

  const second = await context.newPage();
  await second.setViewportSize({ width: 960, height: 600 });
  await startAsParticipant(second, url, secondToken);
  await second.waitForSelector("#queue-banner:not(:empty)");
  const banner = (await second.textContent("#queue-banner")) ?? "";
  check(banner.startsWith("queued: position 1 of 1") && banner.includes("starts by itself"), `p02's banner reads: ${banner}`);
  check(banner.includes("cores"), `p02's banner does not say why: ${banner}`);
  const waiting = await waitFor(second, (s) => s.link.status === "open", { what: "p02's link" });
  check(!waiting.session_active, "p02's session started beside p01's");
  await screenshotStats(second, path.join(artifacts, "queued.png"));
  log(`p02 waits: ${banner}`);

  await page.click("#stop-session");
  await page.click("#stop-confirm");
  await waitFor(page, (s) => s.ended !== null, { what: "p01's session to stop" });
  const started = await waitFor(second, (s) => s.session_active && s.page === "#/teleop", {
    what: "p02's session to start by itself once p01's ended",
  });
  check(((await second.textContent("#queue-banner")) ?? "") === "", "the banner stayed after p02's session started");
  await second.click("#stop-session");
  await second.click("#stop-confirm");
  await waitFor(second, (s) => s.ended !== null, { what: "p02's session to stop" });
  console.log(`RESULT ${JSON.stringify({ first: first.session_id, second: started.session_id, banner })}`);
});
