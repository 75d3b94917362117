"""Session setup: the validated parameters of one operator sitting, from TOML and flags."""

from workcell.session.config import (
    MODES,
    Mode,
    RecordingConfig,
    SessionConfig,
    TaskConfig,
)

__all__ = ["MODES", "Mode", "RecordingConfig", "SessionConfig", "TaskConfig"]
