"""Offscreen rendering of the workcell and its output: PNG pictures and MP4 videos."""

from workcell.render.quality import CAMERA_QUALITY, RENDER_QUALITIES, RenderQuality
from workcell.render.renderer import OffscreenRenderer, camera_names, overview_camera
from workcell.render.snapshot import save_png
from workcell.render.video import VideoWriter

__all__ = [
    "CAMERA_QUALITY",
    "RENDER_QUALITIES",
    "OffscreenRenderer",
    "RenderQuality",
    "VideoWriter",
    "camera_names",
    "overview_camera",
    "save_png",
]
