"""The recorded stores and default LeRobot export of the export tests, shared here."""

from tests.export.conftest import lerobot_dir, recorded

__all__ = ["lerobot_dir", "recorded"]
