// Replay of one recorded trial in the 3D view, from /api/trials/{id}/frames, with
// play/pause, a scrub bar and playback speed, the trial's facts (who, condition, study
// step, outcome, time, boxes) and its event timeline (click an event to go to it). The
// poses are the recorded ones, rebuilt by the server; trial time follows the wall clock
// (replayClock.ts), so a slow renderer skips frames instead of playing slower.

import type { ReplayFacts, TimelineEvent, TrialReplay } from "../protocol";
import { fetchReplay } from "../net/api";
import { Viewer } from "../scene/viewer";
import { exposeExtra } from "../debug";
import { el } from "../util/dom";
import { PlaybackMeter, ReplayClock, frameAt } from "./replayClock";
import { factLines } from "./replayFacts";

export { frameAt } from "./replayClock";

const EVERY = 2;

function factsList(facts: ReplayFacts): HTMLElement {
  const list = el("dl", { className: "replay-facts" });
  for (const [label, value] of factLines(facts)) {
    const dd = el("dd", { textContent: value });
    dd.dataset["fact"] = label;
    list.append(el("dt", { textContent: label }), dd);
  }
  return list;
}

export function mountReplay(root: HTMLElement, trialId: string): () => void {
  const page = el("section", { className: "page replay-page" });
  const viewport = el("div", { className: "viewport replay" });
  const controls = el("div", { className: "replay-controls" });
  const play = el("button", { id: "replay-play", textContent: "Play", disabled: true });
  const scrub = el("input", { id: "replay-scrub", type: "range", min: "0", max: "0", step: "1", value: "0", disabled: true });
  const speed = el("select", { id: "replay-speed" });
  for (const s of ["0.5", "1", "2", "4"]) speed.append(el("option", { value: s, textContent: `${s}×`, selected: s === "1" }));
  const clockLabel = el("span", { className: "replay-clock", textContent: "loading…" });
  const back = el("a", { href: "#/sessions", className: "button", textContent: "Back to sessions" });
  controls.append(back, play, scrub, speed, clockLabel);
  const side = el("aside", { className: "replay-side" });
  const timeline = el("ol", { className: "replay-timeline" });
  const body = el("div", { className: "replay-body" }, viewport, side);
  page.append(el("h1", { textContent: `Replay of trial ${trialId}` }), body, controls);
  root.append(page);

  const viewer = new Viewer();
  viewer.viewMode = "third";
  viewer.mount(viewport);
  const clock = new ReplayClock();
  const meter = new PlaybackMeter();
  let replay: TrialReplay | null = null;
  let index = 0;
  /** Frames drawn while playing, and frames passed over to keep time. */
  let drawn = 0;
  let skipped = 0;

  const recordedFrame = (i: number): number => (replay === null ? 0 : Math.min(i * replay.every, replay.recorded_frames - 1));

  const show = (i: number): void => {
    if (replay === null) return;
    const n = replay.poses.length;
    index = Math.max(0, Math.min(n - 1, i));
    const poses = replay.poses[index];
    if (poses !== undefined) viewer.world.applyPoses(poses);
    scrub.value = String(index);
    const t = replay.t_sim[index] ?? 0;
    const end = replay.t_sim[n - 1] ?? 0;
    // The recorded frame's number, of every recorded frame: what the Sessions page counts.
    clockLabel.textContent = `${t.toFixed(2)} / ${end.toFixed(2)} s · frame ${recordedFrame(index) + 1} of ${replay.recorded_frames}`;
    let current: HTMLElement | null = null;
    for (const item of timeline.querySelectorAll<HTMLElement>("li")) {
      const at = Number(item.dataset["t"]);
      item.classList.remove("current");
      if (at <= t + 1e-9) current = item;
    }
    current?.classList.add("current");
  };

  const setPlaying = (on: boolean): void => {
    const now = performance.now();
    play.textContent = on ? "Pause" : "Play";
    if (replay === null) return;
    if (!on) {
      clock.pause(now);
      return;
    }
    const end = replay.t_sim[replay.t_sim.length - 1] ?? 0;
    let from = replay.t_sim[index] ?? 0;
    if (from >= end) {
      from = replay.t_sim[0] ?? 0;
      show(0);
    }
    clock.play(from, now);
    meter.start(from, now);
  };

  const seek = (i: number): void => {
    if (replay === null) return;
    show(i);
    const now = performance.now();
    clock.seek(replay.t_sim[index] ?? 0, now);
    if (clock.playing) meter.start(replay.t_sim[index] ?? 0, now);
  };

  play.addEventListener("click", () => setPlaying(!clock.playing));
  scrub.addEventListener("input", () => {
    setPlaying(false);
    show(Number(scrub.value));
  });
  speed.addEventListener("change", () => {
    const now = performance.now();
    clock.setSpeed(Number(speed.value), now);
    if (clock.playing && replay !== null) meter.start(replay.t_sim[index] ?? 0, now);
  });

  const showTimeline = (events: readonly TimelineEvent[]): void => {
    timeline.replaceChildren();
    for (const event of events) {
      const item = el("li", { className: `event event-${event.kind}` });
      item.dataset["t"] = String(event.t);
      const go = el("button", { type: "button", className: "small seek", textContent: `${event.t.toFixed(2)} s` });
      go.title = "go to this moment of the trial";
      go.addEventListener("click", () => {
        if (replay !== null) seek(frameAt(replay.t_sim, event.t));
      });
      item.append(go, " ", el("strong", { textContent: event.kind.replaceAll("_", " ") }));
      if (event.detail !== "") item.append(" ", el("span", { className: "detail", textContent: event.detail }));
      timeline.append(item);
    }
    if (events.length === 0) timeline.append(el("li", { textContent: "no events recorded" }));
  };

  const removeFrame = viewer.onFrame((time) => {
    if (replay !== null && clock.playing) {
      const next = frameAt(replay.t_sim, clock.time(time));
      if (next !== index) {
        drawn += 1;
        skipped += Math.max(0, next - index - 1);
        show(next);
        meter.shown(replay.t_sim[index] ?? 0, time);
      }
      if (index >= replay.poses.length - 1) setPlaying(false);
    }
    viewer.placeRig(null);
  });

  const removeExtra = exposeExtra("replay", () => ({
    trial_id: trialId,
    loaded: replay !== null,
    frames: replay?.poses.length ?? 0,
    recorded_frames: replay?.recorded_frames ?? 0,
    index,
    recorded_index: recordedFrame(index),
    playing: clock.playing,
    t: replay?.t_sim[index] ?? null,
    base: viewer.world.bodyPose("base"),
    drawn,
    skipped,
    rate: meter.rate(),
  }));

  fetchReplay(trialId, EVERY)
    .then((result) => {
      replay = result;
      viewer.world.build(result.scene);
      scrub.max = String(Math.max(0, result.poses.length - 1));
      scrub.disabled = false;
      play.disabled = result.poses.length < 2;
      side.append(el("h2", { textContent: "Trial" }), factsList(result.facts), el("h2", { textContent: "Events" }), timeline);
      showTimeline(result.events);
      show(0);
    })
    .catch((error: unknown) => {
      clockLabel.textContent = `Could not load the trial: ${String(error)}`;
    });

  return () => {
    removeExtra();
    removeFrame();
    viewer.dispose();
    page.remove();
  };
}
