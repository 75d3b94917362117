"""The generalization ladder: success per named world with its Wilson 95 % interval, one
line per operator (and task) (:mod:`workcell.audit.ladder`)."""

from __future__ import annotations

import math
from collections.abc import Sequence

from workcell.audit.figures.canvas import figure, png
from workcell.audit.ladder import WORLD_ORDER, Rung

COLOURS = ("#2e7d32", "#1565c0", "#e07b00", "#6a1b9a", "#c62828", "#00838f", "#5d4037")


def _label(rung: Rung, tasks: int) -> str:
    return rung.operator if tasks == 1 else f"{rung.operator} ({rung.task})"


def draw_ladder(rungs: Sequence[Rung]) -> bytes:
    lines: dict[tuple[str, str], list[Rung]] = {}
    for r in rungs:
        lines.setdefault((r.operator, r.task), []).append(r)
    tasks = len({r.task for r in rungs})
    worlds = [w for w in WORLD_ORDER if any(r.world == w for r in rungs)]
    count = len(lines)
    width = 0.5 / max(count, 1)
    with figure(max(5.0, 1.6 * len(worlds) + 2.6), 3.6) as fig:
        ax = fig.subplots()
        for k, mine in enumerate(lines.values()):
            colour = COLOURS[k % len(COLOURS)]
            shift = (k - (count - 1) / 2) * width
            shown = [r for r in mine if r.rollouts and not math.isnan(r.rate)]
            xs = [worlds.index(r.world) + shift for r in shown]
            pct = [100 * r.rate for r in shown]
            below = [100 * (r.rate - r.low) for r in shown]
            above = [100 * (r.high - r.rate) for r in shown]
            ax.errorbar(
                xs,
                pct,
                yerr=[below, above],
                fmt="o-",
                color=colour,
                ecolor=colour,
                elinewidth=1.4,
                capsize=5,
                markersize=6,
                label=_label(mine[0], tasks),
            )
            for x, y, r in zip(xs, pct, shown, strict=True):
                ax.annotate(
                    f"{r.successes}/{r.rollouts}",
                    (x, y),
                    xytext=(6, -4),
                    textcoords="offset points",
                    fontsize=8,
                    color=colour,
                )
        ax.set_xticks(range(len(worlds)), worlds)
        ax.set_xlim(-0.6, len(worlds) - 0.4)
        ax.set_ylim(0, 105)
        ax.set_xlabel("world (narrow to broad)")
        ax.set_ylabel("success rate (%)")
        ax.set_title("Success per world, Wilson 95 % CI")
        ax.legend(loc="best")
        return png(fig)
