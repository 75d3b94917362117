"""A ConfigError as the protocol's field problems: what the client shows beside each field."""

from __future__ import annotations

from workcell.errors import ConfigError, Problem
from workcell.protocol import messages as m
from workcell.protocol.validation import field_problem


def field_problems(error: ConfigError) -> tuple[m.FieldProblem, ...]:
    """One FieldProblem per line of a ConfigError, its parts as data; a line that names no
    field (not a :class:`Problem`) has an empty path and the whole line as ``allowed``."""
    return tuple(
        field_problem(line.path, line.value, line.allowed, line)
        if isinstance(line, Problem)
        else m.FieldProblem(path=(), value=None, allowed=line, message=line)
        for line in error.problems
    )
