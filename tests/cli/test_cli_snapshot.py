"""``workcell snapshot`` run in-process on the real simulation."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from PIL import Image

from workcell.cli import snapshot
from workcell.cli.main import main
from workcell.render import camera_names
from workcell.sim.config import WorldConfig
from workcell.sim.scene import build_world_model


@pytest.fixture(autouse=True)
def _gl(monkeypatch: pytest.MonkeyPatch) -> None:
    """main() sets MUJOCO_GL; keep that from leaking into other tests."""
    monkeypatch.setenv("MUJOCO_GL", os.environ.get("MUJOCO_GL", "egl"))


def _error_lines(err: str) -> list[str]:
    return [line for line in err.splitlines() if line]


@pytest.mark.parametrize("camera", ["overview", "head_cam"])
def test_writes_a_png_of_the_requested_size(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], camera: str
) -> None:
    out = tmp_path / "pics" / f"{camera}.png"
    argv = ["snapshot", "--out", str(out), "--width", "160", "--height", "120"]
    assert main([*argv, "--camera", camera, "--settle", "1"]) == 0
    assert capsys.readouterr().out.strip() == str(out)
    with Image.open(out) as png:
        assert png.format == "PNG"
        assert png.size == (160, 120)


def test_help(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["snapshot", "--help"]) == 0
    out = capsys.readouterr().out
    for option in ("--out", "--width", "--height", "--camera", "--seed", "--settle"):
        assert option in out


def test_camera_choices_are_the_model_cameras() -> None:
    model = build_world_model(WorldConfig())
    assert (snapshot.OVERVIEW, *camera_names(model)) == snapshot.CAMERAS


def test_bad_width_is_one_error_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "x.png"
    assert main(["snapshot", "--out", str(out), "--width", "10"]) == 2
    captured = capsys.readouterr()
    lines = _error_lines(captured.err)
    assert len(lines) == 1
    assert lines[0].startswith("workcell: error: --width = 10")
    assert "64 to 3840" in lines[0]
    assert captured.out == ""
    assert not out.exists()


def test_each_problem_is_its_own_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["snapshot", "--out", str(tmp_path / "x.jpg"), "--height", "5000", "--settle", "-1"]
    assert main(argv) == 2
    lines = _error_lines(capsys.readouterr().err)
    assert len(lines) == 3
    assert all(line.startswith("workcell: error: ") for line in lines)
    assert ".png" in lines[0]
    assert "--height = 5000" in lines[1]
    assert "--settle" in lines[2]


@pytest.mark.parametrize(
    "extra", [["--width", "wide"], ["--camera", "nose_cam"], []], ids=["type", "choice", "no-out"]
)
def test_malformed_arguments_are_one_error_line(
    capsys: pytest.CaptureFixture[str], extra: list[str]
) -> None:
    argv = ["snapshot", *(["--out", "x.png"] if extra else []), *extra]
    assert main(argv) == 2
    lines = _error_lines(capsys.readouterr().err)
    assert len(lines) == 1
    assert lines[0].startswith("workcell: error: ")


def test_seed_decides_where_the_box_lands(tmp_path: Path) -> None:
    def picture(seed: int, name: str) -> bytes:
        out = tmp_path / f"{name}.png"
        argv = ["snapshot", "--out", str(out), "--width", "160", "--height", "120"]
        assert main([*argv, "--seed", str(seed), "--settle", "3"]) == 0
        return out.read_bytes()

    first = picture(0, "first")
    assert picture(0, "again") == first
    assert picture(1, "other") != first
