"""The export-level provenance document shared by every dataset format.

It names the store, the exported sessions with their study tags (participant, condition,
study step: :mod:`workcell.record.study_tags`) and every stored parameter, the selection,
the conventions of the dataset fields and each episode's :class:`Provenance`.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from typing import Any

from workcell import __version__
from workcell.export.boxes import BOX_STATE_CODES, environment_names
from workcell.export.episode_data import CONVENTIONS
from workcell.export.features import ACTION_NAMES, STATE_NAMES
from workcell.export.options import ExportOptions
from workcell.export.provenance import Provenance
from workcell.export.source import ExportSource
from workcell.record.study_tags import StudyTags

FORMAT = "workcell-dataset-provenance"
FORMAT_VERSION = 2
"""2: ``names.environment_state`` lists every number of ``observation.environment_state``
(the boxes, the task's goal, then both relative to the robot, :mod:`workcell.export.relative`);
version 1 listed the boxes only."""


def provenance_document(
    source: ExportSource,
    options: ExportOptions,
    records: Sequence[Provenance],
    camera_sources: Sequence[Mapping[str, Any]] = (),
) -> dict[str, Any]:
    """The document; ``camera_sources``: where each episode's camera images came from
    (see :class:`workcell.export.camera_images.CameraPlan`)."""
    selection = source.selection
    return {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "software_version": __version__,
        "exported_wall": time.time(),
        "store": {
            "path": str(source.path),
            "store_id": source.meta.get("store_id"),
            "software_version": source.meta.get("software_version"),
            "schema_version": source.meta.get("schema_version"),
        },
        "selection": {
            "include_all": options.include_all,
            "audited": options.audited,
            "successes_only": options.successes_only,
            "left_out_not_successful": selection.not_successes,
            "closed_trials": selection.closed,
            "exported": len(selection.episodes),
            "left_out_not_included": selection.excluded,
            "left_out_without_frames": selection.without_frames,
            "left_out": selection.left_out,
        },
        "cameras": list(options.cameras),
        "image_size": [options.image_size.width, options.image_size.height]
        if options.cameras
        else None,
        "camera_sources": [dict(entry) for entry in camera_sources],
        "conventions": CONVENTIONS,
        "names": {
            "state": list(STATE_NAMES),
            "action": list(ACTION_NAMES),
            "environment_state": list(environment_names(source.pool_size, source.goal_names)),
            "box_state_codes": BOX_STATE_CODES,
        },
        "sessions": {
            s.session_id: {
                "mode": s.mode,
                **StudyTags.of(s.operator_id, s.parameters).as_dict(),
                "seed": s.seed,
                "status": s.status,
                "created_wall": s.created_wall,
                "software_version": s.software_version,
                "schema_version": s.schema_version,
                "parameters": s.parameters,
                "thresholds": s.thresholds,
                "metric_definitions": s.metric_definitions,
                "metrics_version": s.metrics_version,
                "joint_order": list(s.joint_order),
            }
            for s in source.sessions
        },
        "episodes": [record.as_dict() for record in records],
    }
