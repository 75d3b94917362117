// End to end: a study participant opens their invite link, reads the instructions,
// cannot start before accepting the consent text, accepts it and starts; the session is the
// one their plan names (their participant id, the plan's condition) and, once its short
// trial is over, their study page says one session is done and asks no consent again. The
// admin page (another browser page, the admin link) lists both participants live and shows
// the one who has run a session.
//
//   npm run build:e2e && node build/e2e/tests/e2e/study.js <server url> <participant token> <admin token>

import path from "node:path";
import { check, log, pageUrl, runScript, screenshotStats, waitFor } from "./lib.js";

const [, , , participantToken, adminToken] = process.argv;

await runScript("study", async ({ url, page, context, artifacts }) => {
  check(participantToken !== undefined && adminToken !== undefined, "usage: study.js URL PARTICIPANT_TOKEN ADMIN_TOKEN");
  await page.goto(pageUrl(url, { token: participantToken, quality: "low" }));
  await waitFor(page, (s) => s.link.status === "open" && s.role === "operator", { what: "the link to open as operator" });
  await page.waitForSelector(".study-page .study-next");
  const who = (await page.textContent(".study-who")) ?? "";
  check(who.includes("participant p01") && who.includes("0 of 2"), `the study page reads: ${who}`);
  check(((await page.textContent(".study-instructions")) ?? "").includes("green zone"), "no instructions shown");
  const nav = await page.$$eval(".topnav a", (links) => links.map((a) => a.textContent ?? ""));
  check(!nav.includes("Sessions"), `a participant's page offers ${nav.join(", ")}`);
  check(await page.isDisabled("button.start"), "Start is enabled before the consent is accepted");
  await screenshotStats(page, path.join(artifacts, "participant.png"));
  await page.check(".study-consent-box");
  await page.click("button.start");
  const started = await waitFor(page, (s) => s.session !== null && s.page === "#/teleop", {
    what: "the planned session to start",
  });
  const settings = started.session?.settings ?? {};
  log(`started ${started.session_id} as ${started.session?.operator_id}, condition ${String(settings["condition"])}`);
  check(started.session?.operator_id === "p01", `the session's operator is ${started.session?.operator_id}`);
  check(settings["condition"] === "assisted" || settings["condition"] === "physical", "the session has no condition");
  await waitFor(page, (s) => s.ended !== null, { what: "the session to end" });

  await page.goto(pageUrl(url, { token: participantToken, quality: "low" }));
  await page.waitForSelector(".study-page .study-next");
  const after = (await page.textContent(".study-who")) ?? "";
  check(after.includes("1 of 2"), `after one session the study page reads: ${after}`);
  check((await page.$(".study-consent-box")) === null, "the consent is asked again");
  check(!(await page.isDisabled("button.start")), "Start is disabled once consent was given");

  const admin = await context.newPage();
  await admin.setViewportSize({ width: 1100, height: 420 });
  await admin.goto(pageUrl(url, { token: adminToken, role: "spectator" }, "#/admin"));
  await admin.waitForSelector('.participants tr[data-participant="p02"]');
  const row = await admin.$$eval('.participants tr[data-participant="p01"] td', (cells) => cells.map((c) => c.textContent ?? ""));
  log(`admin row of p01: ${row.join(" | ")}`);
  check(row[1] === "waiting" && row[2] === "1/2", `the admin page shows p01 as ${row.join(" | ")}`);
  check(row[6] === "0/1", `p01's outcomes read ${row[6]}`);
  const summary = (await admin.textContent(".admin-summary")) ?? "";
  check(summary.includes("sessions running: 0 (at most 2 at once)"), `the admin summary reads: ${summary}`);
  await screenshotStats(admin, path.join(artifacts, "admin.png"));
  console.log(`RESULT ${JSON.stringify({ session_id: started.session_id, admin_row: row })}`);
});
