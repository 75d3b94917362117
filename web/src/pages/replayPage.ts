// Replay of one recorded trial in the 3D view, from /api/trials/{id}/frames, with
// play/pause, a scrub bar and playback speed. The poses are the recorded ones, rebuilt
// by the server; the client only interpolates time to the nearest frame.

import type { TrialReplay } from "../protocol";
import { fetchReplay } from "../net/api";
import { Viewer } from "../scene/viewer";
import { exposeExtra } from "../debug";
import { el } from "../util/dom";

const EVERY = 2;

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
  page.append(el("h1", { textContent: `Replay of trial ${trialId}` }), viewport, controls);
  root.append(page);

  const viewer = new Viewer();
  viewer.viewMode = "third";
  viewer.mount(viewport);
  let replay: TrialReplay | null = null;
  let index = 0;
  let playing = false;
  let playTime = 0;
  let lastTime: number | null = null;

  const show = (i: number): void => {
    if (replay === null) return;
    const n = replay.poses.length;
    index = Math.max(0, Math.min(n - 1, i));
    const poses = replay.poses[index];
    if (poses !== undefined) viewer.world.applyPoses(poses);
    scrub.value = String(index);
    const t = replay.t_sim[index] ?? 0;
    const end = replay.t_sim[n - 1] ?? 0;
    clockLabel.textContent = `${t.toFixed(2)} / ${end.toFixed(2)} s · frame ${index + 1}/${n}`;
  };

  const setPlaying = (on: boolean): void => {
    playing = on;
    play.textContent = on ? "Pause" : "Play";
    if (on && replay !== null) {
      const end = replay.t_sim[replay.t_sim.length - 1] ?? 0;
      playTime = replay.t_sim[index] ?? 0;
      if (playTime >= end) {
        playTime = replay.t_sim[0] ?? 0;
        show(0);
      }
    }
  };

  play.addEventListener("click", () => setPlaying(!playing));
  scrub.addEventListener("input", () => {
    setPlaying(false);
    show(Number(scrub.value));
  });

  const removeFrame = viewer.onFrame((time) => {
    const dt = lastTime === null ? 0 : Math.min(0.1, (time - lastTime) / 1000);
    lastTime = time;
    if (replay === null) return;
    if (playing) {
      playTime += dt * Number(speed.value);
      const next = frameAt(replay.t_sim, playTime);
      if (next !== index) show(next);
      if (index >= replay.poses.length - 1) setPlaying(false);
    }
    viewer.placeRig(null);
  });

  const removeExtra = exposeExtra("replay", () => ({
    trial_id: trialId,
    loaded: replay !== null,
    frames: replay?.poses.length ?? 0,
    index,
    playing,
    t: replay?.t_sim[index] ?? null,
    base: viewer.world.bodyPose("base"),
  }));

  fetchReplay(trialId, EVERY)
    .then((result) => {
      replay = result;
      viewer.world.build(result.scene);
      scrub.max = String(Math.max(0, result.poses.length - 1));
      scrub.disabled = false;
      play.disabled = result.poses.length < 2;
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
