"""Reading the selected episodes of a store, one at a time, for any dataset format."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

from workcell.export.episode_data import EpisodeArrays, episode_arrays
from workcell.export.provenance import Provenance
from workcell.export.replay_world import ReplayWorld, WorldPool
from workcell.export.restore import RecordedStates
from workcell.export.selection import EpisodeSource, Selection
from workcell.export.source import ExportSource
from workcell.record.store import Store

Progress = Callable[[str], None]
"""Receives one line of progress at a time (the command line prints it to stderr)."""


@dataclass(frozen=True)
class ExportSummary:
    """What a dataset export wrote."""

    out: Path
    episodes: int
    frames: int
    videos: int
    """Camera streams per episode."""
    seconds: float
    recorded_videos: int = 0
    """Camera streams (of all episodes) taken from the trials' recorded videos."""
    rendered_videos: int = 0
    """Camera streams (of all episodes) rendered from the recorded states."""
    selection: Selection | None = None
    """Which trials were exported and what was left out, per reason."""


@dataclass(frozen=True)
class LoadedEpisode:
    """One episode's rows, recorded states and provenance."""

    index: int
    source: EpisodeSource
    provenance: Provenance
    arrays: EpisodeArrays
    states: RecordedStates
    world: ReplayWorld | None
    """Its world, replay-checked, when the export restores states (images, MuJoCo states)."""


def load_episodes(
    store: Store, source: ExportSource, worlds: WorldPool | None, progress: Progress | None
) -> Iterator[LoadedEpisode]:
    """The selected episodes in order; each one's world is replay-checked first when
    ``worlds`` is given (raises :class:`ReplayMismatchError` when the check fails)."""
    total = len(source.episodes)
    for index, episode in enumerate(source.episodes):
        trial = episode.trial
        frames = store.frames(trial.trial_id)
        goal = source.goal(store, episode)
        conditions = source.conditions(store, episode)
        arrays = episode_arrays(frames, trial.outcome, source.pool_size, goal, source.goal_names)
        states = RecordedStates.from_frames(frames, arrays.boxes)
        world = None
        if worlds is not None:
            world = worlds.get(source.configs[trial.session_id])
            world.check(states, trial.trial_id)
        provenance = Provenance.of(index, episode, conditions)
        yield LoadedEpisode(index, episode, provenance, arrays, states, world)
        if progress is not None:
            progress(
                f"episode {index + 1}/{total}: trial {trial.trial_id} "
                f"({trial.outcome}, {arrays.length} frames)"
            )
