// The replay's clock: trial time follows the wall clock times the speed, however slowly
// the page draws (a slow renderer shows fewer frames, skipping the ones between, instead
// of playing slower). Pure: the caller passes the wall clock (ms, as performance.now()).

/** The index of the last frame at or before `t` (binary search; times ascend). */
export function frameAt(times: readonly number[], t: number): number {
  let lo = 0;
  let hi = times.length - 1;
  if (hi < 0) return 0;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if ((times[mid] ?? Infinity) <= t) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

export class ReplayClock {
  private anchorTrial = 0;
  private anchorWall = 0;
  private speedFactor = 1;
  private running = false;

  get playing(): boolean {
    return this.running;
  }

  get speed(): number {
    return this.speedFactor;
  }

  /** Trial time (s) at wall time `nowMs`. */
  time(nowMs: number): number {
    if (!this.running) return this.anchorTrial;
    // an animation frame's time may precede the click that started playing: never back
    return this.anchorTrial + (Math.max(0, nowMs - this.anchorWall) / 1000) * this.speedFactor;
  }

  play(fromTrial: number, nowMs: number): void {
    this.anchorTrial = fromTrial;
    this.anchorWall = nowMs;
    this.running = true;
  }

  pause(nowMs: number): void {
    this.anchorTrial = this.time(nowMs);
    this.running = false;
  }

  /** Jump to trial time `t` (playing on from there if playing). */
  seek(t: number, nowMs: number): void {
    this.anchorTrial = t;
    this.anchorWall = nowMs;
  }

  setSpeed(speed: number, nowMs: number): void {
    this.anchorTrial = this.time(nowMs);
    this.anchorWall = nowMs;
    this.speedFactor = speed;
  }
}

/** How fast a replay really went: the trial time of the frames shown against the wall
 * clock when they were shown, from the frame shown as play began to the newest. */
export class PlaybackMeter {
  private first: { t: number; wall: number } | null = null;
  private last: { t: number; wall: number } | null = null;

  /** Playing starts from the frame at trial time `t`, shown at `wallMs`. */
  start(t: number, wallMs: number): void {
    this.first = { t, wall: wallMs };
    this.last = null;
  }

  /** A frame at trial time `t` was shown at `wallMs` while playing. */
  shown(t: number, wallMs: number): void {
    if (this.first !== null) this.last = { t, wall: wallMs };
  }

  /** Trial seconds shown per wall second (null before a second of playing). */
  rate(): number | null {
    if (this.first === null || this.last === null) return null;
    const wall = (this.last.wall - this.first.wall) / 1000;
    return wall >= 1 ? (this.last.t - this.first.t) / wall : null;
  }
}
