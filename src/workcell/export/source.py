"""Opening a store for export: the checks every dataset export makes before writing.

Refused, each with one line saying what to do: an output folder that is not empty, a
store that fails ``workcell verify``, a store without trials, a selection without
episodes, and sessions that cannot share one dataset (different frame rates or box pools).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

from workcell.errors import ConfigError
from workcell.export.audited import audited_inclusions
from workcell.export.errors import (
    EmptyStoreError,
    IncompatibleSessionsError,
    NothingSelectedError,
    OutputNotEmptyError,
    StoreNotVerifiedError,
)
from workcell.export.options import TrialFilter
from workcell.export.selection import EpisodeSource, Selection, select
from workcell.record.entries import SessionRecord
from workcell.record.store import Store
from workcell.record.verify import verify_store
from workcell.session.config import SessionConfig
from workcell.session.toml_io import from_mapping
from workcell.tasks.registry import load_task

T = TypeVar("T")


@dataclass(frozen=True)
class ExportSource:
    """A verified store and the episodes selected from it."""

    path: Path
    meta: dict[str, str]
    """The store's meta table (store_id, software_version, ...)."""
    selection: Selection
    configs: dict[str, SessionConfig]
    """Each exported session's configuration, rebuilt from its stored parameters."""
    fps: int
    pool_size: int
    goal_names: tuple[str, ...]
    """The names of the sessions' task goal (:attr:`workcell.tasks.Task.goal_names`)."""

    @property
    def episodes(self) -> tuple[EpisodeSource, ...]:
        return self.selection.episodes

    @property
    def sessions(self) -> list[SessionRecord]:
        """The exported sessions, in recording order."""
        return _sessions(self.selection)

    def goal(self, store: Store, episode: EpisodeSource) -> tuple[float, ...]:
        """What ``episode``'s trial asked (its task's goal, from its recorded conditions)."""
        config = self.configs[episode.session.session_id]
        return load_task(config.task.kind).goal(self.conditions(store, episode), config.world)

    def conditions(self, store: Store, episode: EpisodeSource) -> Mapping[str, Any]:
        """``episode``'s trial conditions as its ``trial_started`` event recorded them ({}:
        none recorded)."""
        started = store.events(episode.trial.trial_id)
        conditions = next(
            (e.payload.get("conditions") for e in started if e.kind == "trial_started"), None
        )
        return conditions if isinstance(conditions, Mapping) else {}


def check_output(out: str | os.PathLike[str]) -> Path:
    """``out`` if it does not exist or is an empty folder; raises otherwise."""
    path = Path(out)
    if path.exists() and (not path.is_dir() or any(path.iterdir())):
        raise OutputNotEmptyError(
            f"output {path} exists and is not an empty folder; give a new or empty folder"
        )
    return path


def session_config(session: SessionRecord) -> SessionConfig:
    """The configuration a session ran under, rebuilt from its stored parameters."""
    try:
        return from_mapping(SessionConfig, session.parameters)
    except ConfigError as error:
        raise IncompatibleSessionsError(
            f"session {session.session_id}: its stored parameters are not a Workcell session "
            f"configuration ({error.problems[0]}); it cannot be exported as a dataset"
        ) from None


def open_source(path: str | os.PathLike[str], rule: TrialFilter) -> ExportSource:
    """Verify the store at ``path`` and select its episodes by ``rule`` (raises on bad
    input)."""
    path = Path(path)
    findings = verify_store(path)
    if findings:
        raise StoreNotVerifiedError(
            f"store {path} fails verification ({len(findings)} problem"
            f"{'s' if len(findings) > 1 else ''}, first: {findings[0].problem} in "
            f"{findings[0].table} {findings[0].row}); run 'workcell verify --store {path}'"
        )
    with Store.open(path, writer=False) as store:
        if store.counts().trials == 0:
            raise EmptyStoreError(
                f"store {path} holds no trials; record some first "
                f"('workcell collect --store {path}')"
            )
        audited = audited_inclusions(path) if rule.audited else None
        selection = select(store, rule, audited)
        meta = store.meta()
    if not selection.episodes:
        reasons = ", ".join(f"{n} {reason}" for reason, n in selection.left_out.items())
        raise NothingSelectedError(
            f"store {path}: none of its {selection.closed} closed trials can be exported "
            f"(left out: {reasons or 'none closed'})"
            + (
                "; pass --all to export trials that are not included"
                if selection.excluded and not rule.audited
                else ""
            )
        )
    configs = {s.session_id: session_config(s) for s in _sessions(selection)}
    return ExportSource(
        path=path,
        meta=meta,
        selection=selection,
        configs=configs,
        fps=_shared_fps(configs),
        pool_size=_shared(configs, "box pool size", lambda c: c.world.feeder.pool_size),
        goal_names=_shared(configs, "task goal", lambda c: load_task(c.task.kind).goal_names),
    )


def _sessions(selection: Selection) -> list[SessionRecord]:
    seen: dict[str, SessionRecord] = {}
    for episode in selection.episodes:
        seen.setdefault(episode.session.session_id, episode.session)
    return list(seen.values())


def _shared_fps(configs: dict[str, SessionConfig]) -> int:
    rate = _shared(configs, "frame rate", lambda c: c.recording.sampling_rate_hz)
    if abs(rate - round(rate)) > 1e-9:
        raise IncompatibleSessionsError(
            f"frame rate {rate:g} Hz: datasets need a whole number of frames per second"
        )
    return round(rate)


def _shared(configs: dict[str, SessionConfig], what: str, value: Callable[[SessionConfig], T]) -> T:
    values = {session_id: value(config) for session_id, config in configs.items()}
    distinct = set(values.values())
    if len(distinct) > 1:
        listed = ", ".join(f"{sid}: {v}" for sid, v in values.items())
        raise IncompatibleSessionsError(
            f"the selected sessions differ in {what} ({listed}); one dataset needs one "
            "value: export them separately"
        )
    return distinct.pop()
