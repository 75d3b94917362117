"""What a sort trial asks: two kinds of box (their sides, mass and colour), the table each
kind goes to, and each pooled box's kind, drawn from the trial's task stream and recorded
with the trial's conditions (under ``task``), so the judge, the expert, the environment's
goal and the exports all read the same layout."""

from __future__ import annotations

import colorsys
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from workcell.errors import SimulationError
from workcell.sim.config import WorldConfig
from workcell.sim.trial_conditions import TaskValue, TrialConditions

KINDS = 2
"""Kind 0 goes to the delivery table (the factory's), kind 1 to the sorting table."""
SMALL_SCALE = (0.75, 0.85)
"""The smaller kind's sides: this share of the trial's box size (drawn per trial)."""
LARGE_SCALE = (0.95, 1.0)
"""The larger kind's sides: this share of the trial's box size (drawn per trial)."""
HUE_APART = (0.35, 0.65)
"""How far apart on the colour wheel the two kinds' hues are (turns)."""
SATURATION = 0.75
VALUE = 0.8


def sorting_table_center(config: WorldConfig) -> tuple[float, float]:
    """Where the sorting table stands by default: the delivery table mirrored across the
    conveyor's centre line."""
    x, y = config.target.center
    return x, 2 * config.conveyor.center_y - y


@dataclass(frozen=True)
class BoxKind:
    """One kind of box: its sides (along the belt, across, height), mass and colour."""

    size: tuple[float, float, float]
    mass: float
    rgba: tuple[float, float, float, float]


@dataclass(frozen=True)
class SortLayout:
    """``tables``: the centre (x, y) of each kind's zone; ``kinds``: the two kinds;
    ``box_kinds``: the kind of each pooled box, by pool index."""

    tables: tuple[tuple[float, float], tuple[float, float]]
    kinds: tuple[BoxKind, BoxKind]
    box_kinds: tuple[int, ...]

    @staticmethod
    def draw(
        config: WorldConfig, conditions: TrialConditions, rng: np.random.Generator
    ) -> SortLayout:
        """A trial's layout: the sorting table moved as far as the delivery table may be
        (``randomization.target_shift``), one small and one large kind of two distinct
        colours, and the pool's kinds in random order, as even as the pool allows."""
        shift = config.randomization.target_shift
        bx, by = sorting_table_center(config)
        table_b = (
            float(bx + rng.uniform(-shift, shift)),
            float(by + rng.uniform(-shift, shift)),
        )
        scales = (float(rng.uniform(*SMALL_SCALE)), float(rng.uniform(*LARGE_SCALE)))
        small_first = bool(rng.integers(2))
        hue = float(rng.uniform(0.0, 1.0))
        hues = (hue, (hue + float(rng.uniform(*HUE_APART))) % 1.0)
        kinds = []
        for k in range(KINDS):
            scale = scales[0] if (k == 0) == small_first else scales[1]
            s = conditions.box_size
            r, g, b = colorsys.hsv_to_rgb(hues[k], SATURATION, VALUE)
            kinds.append(
                BoxKind(
                    size=(s[0] * scale, s[1] * scale, s[2] * scale),
                    mass=conditions.box_mass * scale**3,
                    rgba=(r, g, b, 1.0),
                )
            )
        pool = config.feeder.pool_size
        even = [k % KINDS for k in range(pool)]
        box_kinds = tuple(int(k) for k in rng.permutation(even))
        return SortLayout((conditions.target_center, table_b), (kinds[0], kinds[1]), box_kinds)

    def kind_of(self, box: int) -> int:
        return self.box_kinds[box]

    def table_of(self, box: int) -> tuple[float, float]:
        """The centre of the zone where pooled box ``box`` belongs."""
        return self.tables[self.box_kinds[box]]

    def recorded(self) -> dict[str, TaskValue]:
        """The layout as the trial's recorded task values."""
        values: dict[str, TaskValue] = {"sorting_table": self.tables[1]}
        for k, kind in enumerate(self.kinds):
            values[f"kind_{k}_size"] = kind.size
            values[f"kind_{k}_mass"] = kind.mass
            values[f"kind_{k}_rgba"] = kind.rgba
        values["box_kinds"] = tuple(float(k) for k in self.box_kinds)
        return values

    @staticmethod
    def from_recorded(values: Mapping[str, Any], delivery_table: Sequence[float]) -> SortLayout:
        """The layout a trial recorded (``values``: its task values, tuples or JSON lists);
        ``delivery_table``: the trial's delivery zone centre."""
        try:
            kinds = tuple(
                BoxKind(
                    size=_three(_floats(values[f"kind_{k}_size"], 3)),
                    mass=float(values[f"kind_{k}_mass"]),
                    rgba=_four(_floats(values[f"kind_{k}_rgba"], 4)),
                )
                for k in range(KINDS)
            )
            table_b = _floats(values["sorting_table"], 2)
            box_kinds = tuple(int(k) for k in values["box_kinds"])
        except (KeyError, TypeError, ValueError) as error:
            raise SimulationError(
                f"the trial's conditions hold no sort layout ({error!r}): a sort trial "
                "records its tables and kinds under conditions.task"
            ) from None
        table_a = (float(delivery_table[0]), float(delivery_table[1]))
        return SortLayout((table_a, (table_b[0], table_b[1])), (kinds[0], kinds[1]), box_kinds)


def _floats(value: Sequence[float], n: int) -> tuple[float, ...]:
    numbers = tuple(float(v) for v in value)
    if len(numbers) != n or not all(math.isfinite(v) for v in numbers):
        raise ValueError(f"expected {n} finite numbers, got {value!r}")
    return numbers


def _three(v: tuple[float, ...]) -> tuple[float, float, float]:
    return v[0], v[1], v[2]


def _four(v: tuple[float, ...]) -> tuple[float, float, float, float]:
    return v[0], v[1], v[2], v[3]
