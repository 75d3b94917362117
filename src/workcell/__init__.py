"""Workcell: a simulated factory for collecting bimanual mobile-manipulation demonstrations.

Importing the package does one thing besides defining the version: on Linux, when
``MUJOCO_GL`` is unset, it selects MuJoCo's EGL backend (``MUJOCO_GL=egl``) for offscreen
rendering, which works with or without a display or GPU (Mesa renders on the CPU). MuJoCo
reads the variable when it is first imported, so this must happen before: ``import
workcell`` (or any ``workcell.*`` module) first. A value set by the user is kept.
"""

import os
import sys

__version__ = "0.1.0"

if sys.platform.startswith("linux") and "mujoco" not in sys.modules:
    os.environ.setdefault("MUJOCO_GL", "egl")
