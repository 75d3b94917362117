"""The single error root of Workcell.

Every error a user can cause derives from :class:`WorkcellError` and carries a message that
names what was wrong and what is allowed, so the command line can print it as one line.
"""

from __future__ import annotations

import math
from collections.abc import Sequence


class WorkcellError(Exception):
    """Root of every error Workcell raises on purpose."""


class Problem(str):
    """One problem line that keeps its parts: ``path`` (the dotted setting name, list
    items indexed: ``task.level_boxes[1]``), the ``value`` given and what is ``allowed``.

    It is the line itself (a ``str``), so it goes wherever a problem line goes, and a
    client can still show the problem beside the field it names without parsing the text.
    The line reads ``path = value: allowed`` unless ``line`` words it otherwise.
    """

    path: str
    value: object
    allowed: str

    def __new__(cls, path: str, value: object, allowed: str, line: str | None = None) -> Problem:
        text = line if line is not None else f"{path} = {_show(value)}: {allowed}"
        problem = super().__new__(cls, text)
        problem.path, problem.value, problem.allowed = path, value, allowed
        return problem

    def under(self, prefix: str) -> Problem:
        """The same problem named from a parent section (``prefix`` ends with a dot)."""
        return Problem(prefix + self.path, self.value, self.allowed, prefix + self)


def _show(value: object) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, tuple):
        return cut("(" + ", ".join(_show(v) for v in value) + ")")
    return shown(value)


LONGEST_SHOWN = 100
"""Characters of a value a problem line shows; a longer one is cut and its length given."""
WIDEST_NUMBER = 30
"""Digits of a whole number a problem line shows; a wider one is shown as its width."""


def shown(value: object, depth: int = 0) -> str:
    """``value`` as a problem line shows it: its ``repr``, but a whole number of more than
    30 digits as its count of digits (Python refuses to write one of more than 4300), lists
    within lists within lists as ``[...]`` and anything longer than 100 characters cut, so
    that a hostile value still makes one short line."""
    if isinstance(value, int) and not isinstance(value, bool):
        digits = decimal_digits(value)
        if digits > WIDEST_NUMBER:
            return f"a {'negative ' if value < 0 else ''}{digits}-digit number"
        return repr(value)
    if isinstance(value, list | tuple):
        inner = "..." if depth >= 2 else ", ".join(shown(v, depth + 1) for v in value[:20])
        if len(value) > 20:
            inner += ", ..."
        return cut(f"[{inner}]" if isinstance(value, list) else f"({inner})")
    if isinstance(value, dict):
        return cut("{...}" if value else "{}")
    try:
        text = repr(value)
    except (ValueError, RecursionError):
        return f"a {type(value).__name__}"
    return cut(text)


def cut(text: str) -> str:
    """``text``, or its first characters and its length when it is longer than 100 (a key
    or value a user typed, in a problem line)."""
    if len(text) <= LONGEST_SHOWN:
        return text
    return f"{text[: LONGEST_SHOWN - 3]}... ({len(text)} characters)"


def decimal_digits(number: int) -> int:
    """How many decimal digits ``number`` has, counted without writing it out."""
    magnitude = abs(number)
    digits = int((max(magnitude.bit_length(), 1) - 1) * math.log10(2)) + 1
    return digits + 1 if magnitude >= 10**digits else digits


class ConfigError(WorkcellError):
    """One or more configuration values are invalid.

    ``problems`` holds one line per invalid field: the field, the value and what is allowed
    (a :class:`Problem` where the field is known, which keeps those parts apart).
    """

    def __init__(self, problems: Sequence[str]) -> None:
        self.problems: tuple[str, ...] = tuple(problems)
        super().__init__("\n".join(self.problems))


class SimulationError(WorkcellError):
    """The simulation reached a state it cannot continue from (for example NaN physics)."""


class RenderError(WorkcellError):
    """Offscreen rendering is unavailable or failed; the message says how to enable it."""


class MetricsError(WorkcellError):
    """Frames or counts given to the metrics are unusable (missing or ragged columns,
    impossible success counts); the message names every offending column or value."""
