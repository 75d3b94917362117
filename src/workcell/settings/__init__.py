"""Settings declared once (default, unit, allowed values, documentation) and everything
generated from the declarations: validation, the TOML template, the setup page's hints and
the README's table; and the one divisibility rule for rates and steps."""

from workcell.settings.declare import (
    Spec,
    declared_default,
    field_doc,
    same_as,
    section,
    setting,
    spec_of,
)
from workcell.settings.rates import divides, steps_per
from workcell.settings.validate import check_as, declared_problems

__all__ = [
    "Spec",
    "check_as",
    "declared_default",
    "declared_problems",
    "divides",
    "field_doc",
    "same_as",
    "section",
    "setting",
    "spec_of",
    "steps_per",
]
