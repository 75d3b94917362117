"""The one rule for rates and steps: a slower rate must divide a faster one into a whole
number of steps (physics steps per control step, physics or control steps per recorded
frame). Validation and every place that needs the step count use these two functions."""

from __future__ import annotations

import math

from workcell import checks

TOLERANCE = 1e-6
"""How far from a whole number a ratio of rates may be (floating-point timesteps)."""
MOST_STEPS = 1_000_000
"""The most steps of a fast rate one step of a slow rate may span. A slower rate (a frame
every 2,500 s at 400 Hz physics) is a typo: 1e-300 Hz would be 4e302 steps, a trial whose
first frame never comes; 1e-310 Hz an infinite ratio, which no step count is."""


def steps_per(fast_hz: float, slow_hz: float) -> int | None:
    """Steps at ``fast_hz`` in one step at ``slow_hz``: a whole number from 1 to
    :data:`MOST_STEPS`, or None when ``slow_hz`` does not divide ``fast_hz`` evenly (or is
    faster, or far slower, or is not a rate)."""
    if not (_rate(fast_hz) and _rate(slow_hz)):
        return None
    ratio = fast_hz / slow_hz
    if not ratio <= MOST_STEPS + TOLERANCE:  # also NaN and the infinity of a tiny rate
        return None
    steps = round(ratio)
    if steps < 1 or abs(ratio - steps) > TOLERANCE:
        return None
    return steps


def _rate(hz: float) -> bool:
    return checks.finite_number(hz) and hz > 0


def _examples(rate_hz: float, into_hz: float) -> str:
    """Up to four whole rates that divide ``into_hz``, the nearest to ``rate_hz``."""
    rates = {
        round(into_hz / k)
        for k in range(1, 2001)
        if into_hz / k >= 1 and abs(into_hz / k - round(into_hz / k)) < 1e-9
    }
    target = rate_hz if _rate(rate_hz) else into_hz / 20
    nearest = sorted(sorted(rates, key=lambda r: abs(math.log(r / target)))[:4])
    words = [str(r) for r in nearest]
    return ", ".join(words[:-1]) + f" or {words[-1]}" if len(words) > 1 else "".join(words)


def divides(key: str, rate_hz: float, into_hz: float, into: str, whole: bool = False) -> list[str]:
    """The problem of the setting ``key`` when ``rate_hz`` does not divide ``into_hz`` (named
    ``into``, e.g. ``the physics rate 1/world.timestep``) into a whole number of steps;
    ``whole``: the rate must also be a whole number of Hz."""
    if steps_per(into_hz, rate_hz) is not None and (not whole or float(rate_hz).is_integer()):
        return []
    kind = "a whole number of Hz that divides" if whole else "divide"
    steps = "steps"
    if _rate(rate_hz) and rate_hz < into_hz / MOST_STEPS:
        steps = f"at most {MOST_STEPS} steps"
    return [
        checks.problem(
            key,
            rate_hz,
            f"must {'be ' if whole else ''}{kind} {into} = {into_hz:g} Hz into a whole number "
            f"of {steps}, e.g. {_examples(rate_hz, into_hz)}",
        )
    ]
