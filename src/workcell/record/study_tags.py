"""Where a session stands in a study, as its stored parameters say: the participant (the
session's operator id), the condition and the study step (which of the participant's
planned sessions it was, from 1; the setting ``study_step``).

Every output a researcher analyses names a trial's study tags the same way, from this one
reading: the audit's trials.csv and report, the dataset exports' provenance (LeRobot,
HDF5, Rerun) and the Sessions page's data. A session outside a study has no condition and
no step; a session recorded before sessions stored their step has none either.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

STUDY_COLUMNS: tuple[str, ...] = ("operator_id", "condition", "study_step")
"""The names of the study tags, as every output's columns or fields call them."""


@dataclass(frozen=True)
class StudyTags:
    operator_id: str
    condition: str | None
    """None: the session belongs to no condition."""
    study_step: int | None
    """None: not a planned session of a study (or not recorded)."""

    @classmethod
    def of(cls, operator_id: str, parameters: Mapping[str, Any]) -> StudyTags:
        """The tags of a session with this operator id and these stored parameters."""
        condition = parameters.get("condition")
        step = parameters.get("study_step")
        return cls(
            operator_id=operator_id,
            condition=condition if isinstance(condition, str) and condition else None,
            study_step=step if type(step) is int and step > 0 else None,
        )

    def as_dict(self) -> dict[str, Any]:
        return {name: getattr(self, name) for name in STUDY_COLUMNS}
