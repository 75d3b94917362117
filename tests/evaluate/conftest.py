"""The LeRobot export the learn tests train on, shared here (one per test session)."""

from tests.export.conftest import lerobot_dir, recorded

__all__ = ["lerobot_dir", "recorded"]
