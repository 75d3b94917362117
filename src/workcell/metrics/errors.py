"""The metrics' error: frames or counts that cannot be measured, named so they can be fixed."""

from __future__ import annotations

from workcell.errors import WorkcellError


class MetricsError(WorkcellError):
    """Frames or counts given to the metrics are unusable.

    Raised for missing or ragged frame columns and for impossible success counts; the
    message names every offending column or value and what is allowed.
    """
