"""``workcell demo`` end to end, in-process: real simulation (box transfer and another task),
real video encoding."""

from __future__ import annotations

import json
from pathlib import Path

import av
import pytest

from workcell.cli.main import main
from workcell.tasks.registry import load_task


def test_demo_json_reports_a_delivery(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "--seed", "3", "--grasp", "physical", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert set(summary) == {
        "task",
        "world",
        "outcome",
        "success",
        "stage",
        "sim_time_s",
        "real_time_factor",
        "delivered",
    }
    assert (summary["task"], summary["world"], summary["outcome"]) == (
        "box_transfer",
        None,
        "success",
    )
    assert summary["success"] is summary["delivered"] is True
    assert summary["stage"] == load_task("box_transfer").stages[-1]
    assert 5.0 < summary["sim_time_s"] < 120.0
    assert summary["real_time_factor"] > 1.0


def test_demo_runs_another_task_in_one_of_its_worlds(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "--task", "shelve", "--world", "D2", "--seed", "3", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (summary["task"], summary["world"], summary["success"]) == ("shelve", "D2", True)
    assert summary["stage"] == load_task("shelve").stages[-1]


def test_demo_text_says_what_happened(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "--seed", "0", "--time-limit", "5"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("box_transfer: timeout after 5.00 s of simulated time, furthest stage ")
    assert "real time" in out


def test_demo_writes_a_video(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    video = tmp_path / "demo.mp4"
    code = main(
        [
            "demo",
            "--seed",
            "0",
            "--time-limit",
            "2",
            "--video",
            str(video),
            "--video-size",
            "160x96",
        ]
    )
    assert code == 0
    assert str(video) in capsys.readouterr().out
    with av.open(str(video)) as container:
        frames = list(container.decode(video=0))
    assert len(frames) == 61  # 30 fps over 2 s of sim time, both ends included
    assert (frames[0].width, frames[0].height) == (160, 96)


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (["--skill", "2"], "--skill"),
        (["--time-limit", "0"], "--time-limit"),
        (["--video", "out.avi"], "--video"),
        (["--video", "out.mp4", "--video-size", "100x7"], "--video-size"),
        (["--grasp", "magnetic"], "--grasp"),
        (["--task", "juggle"], "--task"),
        (["--world", "D9"], "--world"),
    ],
)
def test_demo_bad_input_is_one_error_line(
    args: list[str], field: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["demo", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("workcell: error:")
    assert field in err[0]
