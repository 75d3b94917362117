// Shared helpers of the end-to-end scripts: launch Debian's chromium with playwright-core,
// poll the page's `window.__workcell`, keep screenshots and check they are drawn.
//
// Every script takes the server's base URL as its first argument and exits 0 on success,
// 1 on a failed check (the reason on stderr). Artifacts go to $WORKCELL_ARTIFACTS (or
// web/test-artifacts/<script>), printed as "artifacts: <dir>".

import { mkdirSync, mkdtempSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";

const here = path.dirname(fileURLToPath(import.meta.url));
export const CHROMIUM = process.env.WORKCELL_CHROMIUM ?? "/usr/bin/chromium";
export const CHROMIUM_ARGS = [
  "--headless",
  "--no-sandbox",
  "--disable-gpu",
  "--disable-quic",
  "--no-first-run",
  "--disable-background-networking",
  "--disable-component-update",
  "--disable-sync",
  "--use-angle=swiftshader",
  "--enable-unsafe-swiftshader",
  "--autoplay-policy=no-user-gesture-required",
];

export class CheckFailed extends Error {}

export function check(condition, message) {
  if (!condition) throw new CheckFailed(message);
}

export function log(...parts) {
  const t = (performance.now() / 1000).toFixed(1).padStart(6);
  console.log(`[${t}s]`, ...parts);
}

export function artifactsDir(name) {
  const dir = process.env.WORKCELL_ARTIFACTS
    ? path.join(process.env.WORKCELL_ARTIFACTS, name)
    : path.resolve(here, "..", "..", "test-artifacts", name);
  mkdirSync(dir, { recursive: true });
  console.log(`artifacts: ${dir}`);
  return dir;
}

/** A fresh browser profile each run; returns { context, page, close }. */
export async function launch({ width = 960, height = 600 } = {}) {
  const profile = mkdtempSync(path.join(tmpdir(), "workcell-chromium-"));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: CHROMIUM,
    headless: true,
    args: CHROMIUM_ARGS,
    viewport: { width, height },
  });
  const page = context.pages()[0] ?? (await context.newPage());
  const consoleLines = [];
  page.on("console", (message) => {
    const line = `${message.type()}: ${message.text()}`;
    consoleLines.push(line);
    if (message.type() === "error") console.error(`page ${line}`);
  });
  page.on("pageerror", (error) => {
    consoleLines.push(`pageerror: ${error.message}`);
    console.error(`page error: ${error.message}`);
  });
  const close = async () => {
    await context.close().catch(() => {});
    rmSync(profile, { recursive: true, force: true });
  };
  return { context, page, consoleLines, close };
}

export const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/** The page's state as `window.__workcell.snapshot()` gives it (null before the app runs). */
export async function snapshot(page) {
  return page.evaluate(() => (window.__workcell ? window.__workcell.snapshot() : null));
}

/** Poll `predicate(snapshot)` until it holds; returns the snapshot. */
export async function waitFor(page, predicate, { timeout = 15000, every = 100, what = "condition" } = {}) {
  const deadline = performance.now() + timeout;
  let last = null;
  while (performance.now() < deadline) {
    last = await snapshot(page);
    if (last !== null && predicate(last)) return last;
    await sleep(every);
  }
  throw new CheckFailed(`timed out after ${timeout} ms waiting for ${what}; last page state: ${JSON.stringify(summary(last))}`);
}

export function summary(s) {
  if (s === null) return null;
  return {
    page: s.page,
    link: s.link,
    role: s.role,
    session_active: s.session_active,
    hud: s.hud,
    holding: s.holding,
    state: s.state && { seq: s.state.seq, t_sim: s.state.t_sim, following: s.state.following },
    teleop: s.teleop && { presenting: s.teleop.presenting, inputs_sent: s.teleop.inputs_sent, xr_frames: s.teleop.xr_frames },
    errors: s.errors,
    events: (s.events ?? []).map((e) => e.kind),
  };
}

/**
 * Save a screenshot (of `locator` or the page) and measure it inside the browser: the
 * luminance variance and the number of distinct colours. A blank canvas has ~0 variance.
 */
export async function screenshotStats(page, file, locator = null) {
  const buffer = locator ? await locator.screenshot({ path: file }) : await page.screenshot({ path: file });
  const stats = await imageStats(page, `data:image/png;base64,${buffer.toString("base64")}`);
  log(`screenshot ${path.basename(file)}: ${stats.width}x${stats.height}, luminance variance ${stats.variance.toFixed(1)}, ${stats.colours} colours`);
  return stats;
}

/** Luminance mean and variance and (sampled) distinct colours of an image, measured in
 * the page (no image library needed in node). */
export async function imageStats(page, dataUrl) {
  return page.evaluate(async (url) => {
    const image = new Image();
    image.src = url;
    await image.decode();
    const canvas = document.createElement("canvas");
    canvas.width = image.width;
    canvas.height = image.height;
    const context = canvas.getContext("2d");
    context.drawImage(image, 0, 0);
    const { data } = context.getImageData(0, 0, image.width, image.height);
    let sum = 0;
    let sumSq = 0;
    const colours = new Set();
    const n = data.length / 4;
    for (let i = 0; i < data.length; i += 4) {
      const y = 0.299 * data[i] + 0.587 * data[i + 1] + 0.114 * data[i + 2];
      sum += y;
      sumSq += y * y;
      if (i % 64 === 0) colours.add((data[i] << 16) | (data[i + 1] << 8) | data[i + 2]);
    }
    const mean = sum / n;
    return { width: image.width, height: image.height, mean, variance: sumSq / n - mean * mean, colours: colours.size };
  }, dataUrl);
}

export function writeJson(file, value) {
  writeFileSync(file, JSON.stringify(value, null, 2));
}

/** Run `body` with a launched browser; exit code 0 on success, 1 on a failed check. */
export async function runScript(name, body) {
  const url = process.argv[2];
  if (!url) {
    console.error(`usage: node ${name}.mjs <server url>`);
    process.exit(2);
  }
  const artifacts = artifactsDir(name);
  const started = performance.now();
  const browser = await launch();
  let code = 0;
  try {
    await body({ url: url.replace(/\/$/, ""), artifacts, ...browser });
    log(`PASS ${name} in ${((performance.now() - started) / 1000).toFixed(1)} s`);
  } catch (error) {
    code = 1;
    console.error(`FAIL ${name}: ${error instanceof CheckFailed ? error.message : error?.stack ?? error}`);
    await browser.page.screenshot({ path: path.join(artifacts, "failure.png") }).catch(() => {});
    const last = await snapshot(browser.page).catch(() => null);
    if (last !== null) writeJson(path.join(artifacts, "failure-state.json"), last);
    writeFileSync(path.join(artifacts, "console.log"), browser.consoleLines.join("\n"));
  } finally {
    await browser.close();
  }
  process.exit(code);
}

/** Compose a URL on the server with extra query parameters (the token rides along). */
export function pageUrl(base, query = {}, hash = "#/") {
  const url = new URL(base + "/");
  for (const [k, v] of Object.entries(query)) url.searchParams.set(k, v);
  return url.toString().replace(/#.*$/, "") + hash;
}
