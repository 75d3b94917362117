"""``export_rerun``: one Rerun recording (``.rrd``) per selected trial, for review in the
Rerun viewer (``rerun DIR/*.rrd``).

::

    DIR/episode_<i>_<trial_id>.rrd   one recording per episode, i = the episode index
                                     (4 digits); application id "workcell", recording id
                                     the trial id; a default blueprint; entities as in
                                     :mod:`workcell.export.rerun_layout`
    DIR/workcell_provenance.json     the export's provenance document (every episode)

Selection, the bad-input checks and the provenance are those of every dataset export
(:mod:`.source`, :mod:`.selection`, :mod:`.provenance`, :mod:`.manifest`). Files are
written with rerun-sdk 0.26 (pinned, as LeRobot 0.4 pins it): open them with the Rerun
viewer 0.26 (``rerun`` of ``pip install rerun-sdk==0.26.2``, or of LeRobot's install).
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import Any

import rerun as rr

from workcell.errors import ConfigError
from workcell.export.boxes import parse_boxes
from workcell.export.loading import ExportSummary, Progress
from workcell.export.manifest import provenance_document
from workcell.export.options import ExportOptions
from workcell.export.provenance import Provenance
from workcell.export.rerun_layout import APPLICATION_ID, TrialRecording, blueprint, log_trial
from workcell.export.selection import EpisodeSource
from workcell.export.source import ExportSource, check_output, open_source
from workcell.record.entries import EventRecord
from workcell.record.store import Store
from workcell.tasks.registry import recorded_task
from workcell.tasks.task import ObjectLook

PROVENANCE_NAME = "workcell_provenance.json"
TRIAL_STARTED = "trial_started"


def recording_name(index: int, trial_id: str) -> str:
    """The file of episode ``index``: ``episode_0003_<trial_id>.rrd``."""
    return f"episode_{index:04d}_{trial_id}.rrd"


def export_rerun(
    store_path: str | os.PathLike[str],
    out_dir: str | os.PathLike[str],
    options: ExportOptions | None = None,
    progress: Progress | None = None,
) -> ExportSummary:
    """Export the store's selected trials into ``out_dir`` (new or empty), one ``.rrd``
    recording each."""
    started = time.perf_counter()
    options = options or ExportOptions()
    if options.cameras:
        raise ConfigError(["cameras: the rerun export does not render camera images"])
    out = check_output(out_dir)
    source = open_source(store_path, options.trials)
    out.mkdir(parents=True, exist_ok=True)
    records: list[Provenance] = []
    frames = 0
    total = len(source.episodes)
    with Store.open(source.path, writer=False) as store:
        for index, episode in enumerate(source.episodes):
            trial = read_trial(store, source, options, index, episode)
            write_recording(out / recording_name(index, episode.trial.trial_id), trial)
            records.append(trial.provenance)
            frames += trial.length
            if progress is not None:
                progress(
                    f"episode {index + 1}/{total}: trial {episode.trial.trial_id} "
                    f"({episode.trial.outcome}, {trial.length} frames)"
                )
    document = provenance_document(source, options, records)
    (out / PROVENANCE_NAME).write_text(json.dumps(document, indent=4) + "\n")
    seconds = time.perf_counter() - started
    return ExportSummary(out, len(records), frames, 0, seconds, selection=source.selection)


def read_trial(
    store: Store, source: ExportSource, options: ExportOptions, index: int, episode: EpisodeSource
) -> TrialRecording:
    """One episode's frames, events, boxes and provenance, as its recording shows them."""
    trial = episode.trial
    frames = store.frames(trial.trial_id)
    events = store.events(trial.trial_id)
    conditions = _conditions(events)
    provenance = Provenance.of(index, episode, conditions)
    world = source.configs[trial.session_id].world
    size = conditions.get("box_size", world.box.size)
    rgba = conditions.get("box_rgba", world.box.rgba)
    trial_box = ObjectLook(
        (float(size[0]), float(size[1]), float(size[2])),
        (float(rgba[0]), float(rgba[1]), float(rgba[2]), float(rgba[3])),
    )
    task = recorded_task(episode.session.parameters)
    return TrialRecording(
        provenance=provenance,
        document=_episode_document(source, options, provenance),
        frames=frames,
        boxes=parse_boxes(frames["boxes"], source.pool_size),
        box_looks=task.object_looks(conditions, source.pool_size, trial_box),
        events=events,
        started_wall=trial.started_wall,
    )


def write_recording(path: Path, trial: TrialRecording) -> None:
    """Write ``trial`` as a complete ``.rrd`` file (footer included) at ``path``."""
    stream = rr.RecordingStream(
        APPLICATION_ID, recording_id=trial.provenance.trial_id, send_properties=False
    )
    stream.save(path, default_blueprint=blueprint())
    try:
        log_trial(stream, trial)
    finally:
        stream.disconnect()  # flushes and finalizes the file


def _conditions(events: list[EventRecord]) -> dict[str, Any]:
    """The trial's conditions, as its ``trial_started`` event recorded them ({} if none)."""
    for event in events:
        if event.kind == TRIAL_STARTED:
            conditions = event.payload.get("conditions")
            return conditions if isinstance(conditions, dict) else {}
    return {}


def _episode_document(
    source: ExportSource, options: ExportOptions, provenance: Provenance
) -> dict[str, Any]:
    """The export's provenance document, narrowed to one episode and its session."""
    document = provenance_document(source, options, [provenance])
    sessions = document["sessions"]
    document["sessions"] = {provenance.session_id: sessions[provenance.session_id]}
    return document
