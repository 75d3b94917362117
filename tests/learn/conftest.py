"""The recorded stores and LeRobot exports of the export tests, shared here."""

from tests.export.conftest import lerobot_dir, lerobot_video_dir, recorded

__all__ = ["lerobot_dir", "lerobot_video_dir", "recorded"]
