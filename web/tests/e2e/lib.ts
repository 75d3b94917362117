// The harness of the end-to-end scripts: launch Debian's chromium with playwright-core,
// poll the page's `window.__workcell` (typed by src/debugSnapshot.ts), keep screenshots
// and check they are drawn, and run a script's body with one exit-code convention.
//
// Every script takes the server's base URL as its first argument and exits 0 on success,
// 1 on a failed check (the reason on stderr). Artifacts go to $WORKCELL_ARTIFACTS (or
// web/test-artifacts/<script>), printed as "artifacts: <dir>". The scripts are compiled
// with `npm run build:e2e` (strict TypeScript) into web/build/e2e and run with node there.

import { mkdirSync, mkdtempSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import path from "node:path";
import { chromium } from "playwright-core";
import type { BrowserContext, Locator, Page } from "playwright-core";
import type { DebugSnapshot } from "../../src/debugSnapshot";

export type { DebugSnapshot } from "../../src/debugSnapshot";

/** web/: the scripts run from there (pytest and `npm run test:e2e` both do). */
const WEB_DIR = process.cwd();
export const CHROMIUM = process.env["WORKCELL_CHROMIUM"] ?? "/usr/bin/chromium";
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

export function check(condition: unknown, message: string): asserts condition {
  if (!condition) throw new CheckFailed(message);
}

export function log(...parts: unknown[]): void {
  const t = (performance.now() / 1000).toFixed(1).padStart(6);
  console.log(`[${t}s]`, ...parts);
}

export function artifactsDir(name: string): string {
  const root = process.env["WORKCELL_ARTIFACTS"];
  const dir = root !== undefined && root !== "" ? path.join(root, name) : path.resolve(WEB_DIR, "test-artifacts", name);
  mkdirSync(dir, { recursive: true });
  console.log(`artifacts: ${dir}`);
  return dir;
}

export interface Browser {
  context: BrowserContext;
  page: Page;
  consoleLines: string[];
  close: () => Promise<void>;
}

/** A fresh browser profile each run. */
export async function launch({ width = 960, height = 600 } = {}): Promise<Browser> {
  const profile = mkdtempSync(path.join(tmpdir(), "workcell-chromium-"));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: CHROMIUM,
    headless: true,
    args: CHROMIUM_ARGS,
    viewport: { width, height },
  });
  const page = context.pages()[0] ?? (await context.newPage());
  const consoleLines: string[] = [];
  page.on("console", (message) => {
    const line = `${message.type()}: ${message.text()}`;
    consoleLines.push(line);
    if (message.type() === "error") console.error(`page ${line}`);
  });
  page.on("pageerror", (error) => {
    consoleLines.push(`pageerror: ${error.message}`);
    console.error(`page error: ${error.message}`);
  });
  const close = async (): Promise<void> => {
    await context.close().catch(() => undefined);
    rmSync(profile, { recursive: true, force: true });
  };
  return { context, page, consoleLines, close };
}

export const sleep = (ms: number): Promise<void> => new Promise((resolve) => setTimeout(resolve, ms));

/** The page's state as `window.__workcell.snapshot()` gives it (null before the app runs). */
export async function snapshot(page: Page): Promise<DebugSnapshot | null> {
  return page.evaluate(() => window.__workcell?.snapshot() ?? null);
}

export interface WaitOptions {
  timeout?: number;
  every?: number;
  what?: string;
}

/** How long a wait for the page's state gives a condition to come true, unless told: long
 * enough for a machine busy with other work (a wait ends as soon as its condition holds, so
 * a generous budget costs nothing where things go well). */
export const PATIENCE_MS = 60000;

/** Poll `predicate(snapshot)` until it holds; returns the snapshot. */
export async function waitFor(
  page: Page,
  predicate: (s: DebugSnapshot) => boolean,
  { timeout = PATIENCE_MS, every = 100, what = "condition" }: WaitOptions = {},
): Promise<DebugSnapshot> {
  const deadline = performance.now() + timeout;
  let last: DebugSnapshot | null = null;
  while (performance.now() < deadline) {
    last = await snapshot(page);
    if (last !== null && predicate(last)) return last;
    await sleep(every);
  }
  throw new CheckFailed(`timed out after ${timeout} ms waiting for ${what}; last page state: ${JSON.stringify(summary(last))}`);
}

/** Until the teleop view has drawn `count` more frames than now (a screenshot then shows
 * what the page draws now, however slowly it draws). */
export async function waitForFrames(page: Page, count = 3): Promise<void> {
  const from = (await snapshot(page))?.teleop?.frames ?? 0;
  await waitFor(page, (s) => (s.teleop?.frames ?? 0) >= from + count, { what: `${count} more frames drawn` });
}

export function summary(s: DebugSnapshot | null): object | null {
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
    events: s.events.map((e) => e.kind),
  };
}

export interface ImageStats {
  width: number;
  height: number;
  mean: number;
  variance: number;
  colours: number;
}

/**
 * Save a screenshot (of `locator` or the page) and measure it inside the browser: the
 * luminance variance and the number of distinct colours. A blank canvas has ~0 variance.
 */
export async function screenshotStats(page: Page, file: string, locator: Locator | null = null): Promise<ImageStats> {
  const buffer = locator ? await locator.screenshot({ path: file }) : await page.screenshot({ path: file });
  const stats = await imageStats(page, `data:image/png;base64,${buffer.toString("base64")}`);
  log(`screenshot ${path.basename(file)}: ${stats.width}x${stats.height}, luminance variance ${stats.variance.toFixed(1)}, ${stats.colours} colours`);
  return stats;
}

/** Luminance mean and variance and (sampled) distinct colours of an image, measured in
 * the page (no image library needed in node). */
export async function imageStats(page: Page, dataUrl: string): Promise<ImageStats> {
  return page.evaluate(async (url) => {
    const image = new Image();
    image.src = url;
    await image.decode();
    const canvas = document.createElement("canvas");
    canvas.width = image.width;
    canvas.height = image.height;
    const context = canvas.getContext("2d");
    if (context === null) throw new Error("no 2D canvas");
    context.drawImage(image, 0, 0);
    const { data } = context.getImageData(0, 0, image.width, image.height);
    let sum = 0;
    let sumSq = 0;
    const colours = new Set<number>();
    const n = data.length / 4;
    for (let i = 0; i < data.length; i += 4) {
      const r = data[i] ?? 0;
      const g = data[i + 1] ?? 0;
      const b = data[i + 2] ?? 0;
      const y = 0.299 * r + 0.587 * g + 0.114 * b;
      sum += y;
      sumSq += y * y;
      if (i % 64 === 0) colours.add((r << 16) | (g << 8) | b);
    }
    const mean = sum / n;
    return { width: image.width, height: image.height, mean, variance: sumSq / n - mean * mean, colours: colours.size };
  }, dataUrl);
}

/** Check that a screenshot shows something drawn (not a blank canvas). */
export async function checkDrawn(page: Page, file: string, locator: Locator | null = null, minVariance = 50): Promise<ImageStats> {
  const stats = await screenshotStats(page, file, locator);
  check(stats.variance > minVariance && stats.colours > 20, `${path.basename(file)} looks blank (variance ${stats.variance.toFixed(1)}, ${stats.colours} colours)`);
  return stats;
}

export function writeJson(file: string, value: unknown): void {
  writeFileSync(file, JSON.stringify(value, null, 2));
}

export interface ScriptContext extends Browser {
  url: string;
  artifacts: string;
}

/** Run `body` with a launched browser; exit code 0 on success, 1 on a failed check. */
export async function runScript(name: string, body: (context: ScriptContext) => Promise<void>): Promise<never> {
  const url = process.argv[2];
  if (url === undefined || url === "") {
    console.error(`usage: node ${name}.js <server url>`);
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
    const reason = error instanceof CheckFailed ? error.message : error instanceof Error ? (error.stack ?? error.message) : String(error);
    console.error(`FAIL ${name}: ${reason}`);
    await browser.page.screenshot({ path: path.join(artifacts, "failure.png") }).catch(() => undefined);
    const last = await snapshot(browser.page).catch(() => null);
    if (last !== null) writeJson(path.join(artifacts, "failure-state.json"), last);
    writeFileSync(path.join(artifacts, "console.log"), browser.consoleLines.join("\n"));
  } finally {
    await browser.close();
  }
  process.exit(code);
}

/** Compose a URL on the server with extra query parameters (the token rides along). */
export function pageUrl(base: string, query: Record<string, string> = {}, hash = "#/"): string {
  const url = new URL(base + "/");
  for (const [k, v] of Object.entries(query)) url.searchParams.set(k, v);
  return url.toString().replace(/#.*$/, "") + hash;
}
