"""The audit's parameters, one frozen value written whole into every report."""

from __future__ import annotations

import inspect
from dataclasses import asdict, dataclass, field
from types import ModuleType
from typing import Any, Literal

from workcell.audit import (
    crosscheck,
    disposition,
    nonfinite,
    oscillation,
    sampling,
    slowness,
    wilcoxon,
)
from workcell.audit.crosscheck import CROSSCHECKED, Tolerance
from workcell.audit.nonfinite import NONFINITE_VERSION, NonfiniteParams
from workcell.audit.oscillation import OSCILLATION_VERSION, OscillationParams
from workcell.audit.sampling import SAMPLING_VERSION, SamplingParams
from workcell.audit.slowness import SLOWNESS_VERSION, SlownessParams
from workcell.audit.wilcoxon import WILCOXON_VERSION, PairedParams
from workcell.errors import ConfigError
from workcell.settings import declared_problems, setting
from workcell.study.config import StudyConfig

CompareBy = Literal["operator", "condition"]
"""What the audit's comparison groups trials by (:mod:`workcell.audit.comparison`)."""
CompareChoice = Literal["none", "operator", "condition"]
"""The setting ``compare_by``: a :data:`CompareBy`, or no comparison."""

AUDIT_VERSION = "3"
"""Bumped whenever dispositions, statistics or the report's files change meaning (2:
trials.csv ends with each trial's operator_id, condition and study_step; 3: ``--by
condition`` on a within-subject design compares conditions within participants, by the
Wilcoxon signed-rank test, in summary.json's ``comparison.paired``, instead of the pooled
tests, whose ``comparison.pairs`` is then empty)."""


def _doc(module: ModuleType) -> str:
    return inspect.cleandoc(module.__doc__ or "")


DEFINITIONS: dict[str, str] = {
    "crosscheck": _doc(crosscheck),
    "arm_oscillation": _doc(oscillation),
    "sampling": _doc(sampling),
    "nonfinite": _doc(nonfinite),
    "slow": _doc(slowness),
    "dispositions": _doc(disposition),
    "paired": _doc(wilcoxon),
}
"""The written definition of every check and rule, as in their modules (versioned there)."""


def _study(study: StudyConfig) -> dict[str, Any]:
    return {
        "name": study.name,
        "participants": study.participants,
        "order": study.order,
        "seed": study.seed,
        "conditions": [c.name for c in study.conditions],
        "steps": [{"mode": s.mode, "trials": s.trials} for s in study.steps],
    }


@dataclass(frozen=True)
class AuditConfig:
    """Cross-check tolerance, detector parameters and how many successful trials the
    trajectory figure draws (temporally stratified)."""

    tolerance: Tolerance = field(default_factory=Tolerance)
    oscillation: OscillationParams = field(default_factory=OscillationParams)
    sampling: SamplingParams = field(default_factory=SamplingParams)
    nonfinite: NonfiniteParams = field(default_factory=NonfiniteParams)
    slowness: SlownessParams = field(default_factory=SlownessParams)
    trajectories: int = setting(
        30, "successful trials the trajectory figure draws", unit="trials", low=1, high=1000
    )
    compare_by: CompareChoice = setting(
        "none",
        "compare groups of trials by operator or by study condition (none: no comparison)",
    )
    paired: PairedParams = field(default_factory=PairedParams)
    study: StudyConfig | None = None
    """The study the trials belong to (``--study FILE``): its name, design and plan."""

    def __post_init__(self) -> None:
        problems = declared_problems(self, "")
        if problems:
            raise ConfigError(problems)

    def describe(self) -> dict[str, Any]:
        """Every parameter with its definition's version (for summary.json and the report)."""
        return {
            "audit_version": AUDIT_VERSION,
            "crosscheck": {"metrics": list(CROSSCHECKED), **asdict(self.tolerance)},
            "detectors": {
                "arm_oscillation": {"version": OSCILLATION_VERSION, **asdict(self.oscillation)},
                "sampling": {"version": SAMPLING_VERSION, **asdict(self.sampling)},
                "nonfinite": {"version": NONFINITE_VERSION, **asdict(self.nonfinite)},
                "slow": {"version": SLOWNESS_VERSION, **asdict(self.slowness)},
            },
            "trajectories": self.trajectories,
            "compare_by": self.compare_by,
            "paired": {"version": WILCOXON_VERSION, **asdict(self.paired)},
            "study": None if self.study is None else _study(self.study),
            "definitions": DEFINITIONS,
        }
