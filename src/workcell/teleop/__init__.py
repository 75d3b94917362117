"""Teleoperation: a browser's raw device state (poses, grips, triggers, sticks) → Commands."""
