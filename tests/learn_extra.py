"""Tests that need the learn extra (LeRobot, torch, robomimic: ``workcell[learn]``).

They run wherever the extra is installed. Without it they skip, unless
``WORKCELL_LEARN_TESTS=require`` (``make test`` and CI, which install the extra first),
where the missing extra fails them instead::

    from tests.learn_extra import require_learn_extra

    def test_x() -> None:
        require_learn_extra()
        import lerobot
"""

from __future__ import annotations

import importlib.util
import os

import pytest

REQUIRED = os.environ.get("WORKCELL_LEARN_TESTS") == "require"
MODULES = ("lerobot", "torch", "robomimic")


def missing_modules() -> list[str]:
    """The learn extra's modules that cannot be imported here."""
    return [name for name in MODULES if importlib.util.find_spec(name) is None]


def require_learn_extra() -> None:
    """Skip the calling test without the learn extra (fail instead when it is required)."""
    missing = missing_modules()
    if not missing:
        return
    reason = f"the learn extra is not installed ({', '.join(missing)} missing): make setup-learn"
    if REQUIRED:
        pytest.fail(reason)
    pytest.skip(reason)
