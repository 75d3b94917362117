"""What can go wrong before generation starts."""

from __future__ import annotations

from workcell.errors import WorkcellError


class GenerateError(WorkcellError):
    """The source store, its trials or the generation's settings cannot be used."""
