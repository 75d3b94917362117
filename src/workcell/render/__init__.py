"""Offscreen rendering of the workcell and its output: PNG pictures and MP4 videos."""

from workcell.render.renderer import OffscreenRenderer, camera_names, overview_camera
from workcell.render.snapshot import save_png
from workcell.render.video import VideoWriter

__all__ = ["OffscreenRenderer", "VideoWriter", "camera_names", "overview_camera", "save_png"]
