"""Workcell: a simulated factory for collecting bimanual mobile-manipulation demonstrations."""

__version__ = "0.1.0"
