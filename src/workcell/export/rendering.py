"""Re-rendering recorded trials from their states: one MP4 per trial and camera.

Each trial is replay-checked first (:mod:`workcell.export.replay`), then every frame is
restored and rendered at the requested size, at the session's frame rate.
"""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from workcell.export.errors import NothingSelectedError, OutputNotEmptyError, UnknownTrialError
from workcell.export.loading import Progress
from workcell.export.options import ImageSize
from workcell.export.replay import ReplayErrors
from workcell.export.replay_world import WorldPool
from workcell.export.restore import RecordedStates
from workcell.export.source import session_config
from workcell.record.entries import TrialRecord
from workcell.record.store import Store
from workcell.render.video import VideoWriter

PROGRESS_FRAMES = 200
"""Report progress every this many frames of a trial."""


@dataclass(frozen=True)
class RenderedTrial:
    trial_id: str
    frames: int
    videos: tuple[Path, ...]
    replay: ReplayErrors
    seconds: float


def video_name(trial_id: str, camera: str) -> str:
    return f"{trial_id}_{camera}.mp4"


def render_trials(
    store_path: str | os.PathLike[str],
    out_dir: str | os.PathLike[str],
    cameras: Sequence[str],
    size: ImageSize,
    *,
    trial_ids: Sequence[str] = (),
    progress: Progress | None = None,
) -> list[RenderedTrial]:
    """Render ``trial_ids`` (default: every trial with frames) into ``out_dir``."""
    out = Path(out_dir)
    results = []
    with Store.open(store_path, writer=False) as store, WorldPool(size) as worlds:
        trials = _chosen(store, trial_ids)
        for trial in trials:
            targets = [out / video_name(trial.trial_id, camera) for camera in cameras]
            existing = [str(path) for path in targets if path.exists()]
            if existing:
                raise OutputNotEmptyError(
                    f"{existing[0]} exists; remove it or choose another --out"
                )
        sessions = {s.session_id: s for s in store.sessions()}
        for number, trial in enumerate(trials, 1):
            started = time.perf_counter()
            config = session_config(sessions[trial.session_id])
            fps = round(config.recording.sampling_rate_hz)
            states = RecordedStates.from_frames(store.frames(trial.trial_id))
            world = worlds.get(config)
            replay = world.check(states, trial.trial_id)
            paths = tuple(out / video_name(trial.trial_id, camera) for camera in cameras)
            writers = [VideoWriter(path, size.width, size.height, fps) for path in paths]
            try:
                for i, images in enumerate(world.images(states, cameras)):
                    for writer, camera in zip(writers, cameras, strict=True):
                        writer.write(images[camera])
                    if progress is not None and (i + 1) % PROGRESS_FRAMES == 0:
                        progress(f"trial {number}/{len(trials)}: frame {i + 1}/{len(states)}")
            finally:
                for writer in writers:
                    writer.close()
            result = RenderedTrial(
                trial.trial_id, len(states), paths, replay, time.perf_counter() - started
            )
            results.append(result)
            if progress is not None:
                progress(
                    f"trial {number}/{len(trials)}: {trial.trial_id}, {len(states)} frames, "
                    f"replay error {replay.position_m:.2g} m, {result.seconds:.1f} s"
                )
    return results


def _chosen(store: Store, trial_ids: Sequence[str]) -> list[TrialRecord]:
    trials = [t for t in store.trials() if t.n_frames or t.outcome is None]
    if not trial_ids:
        if not trials:
            raise NothingSelectedError(f"store {store.path} holds no trial with frames")
        return trials
    by_id = {t.trial_id: t for t in store.trials()}
    unknown = [trial_id for trial_id in trial_ids if trial_id not in by_id]
    if unknown:
        raise UnknownTrialError(
            f"--trial {unknown[0]}: no such trial in store {store.path}; the trial ids are "
            "in trials.csv of 'workcell export --format csv'"
        )
    return [by_id[trial_id] for trial_id in dict.fromkeys(trial_ids)]
