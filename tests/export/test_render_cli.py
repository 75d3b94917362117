"""``workcell render``, run through its own parser as the other command tests do."""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path

import pytest

from tests.export.stores import Stores
from workcell.cli import render
from workcell.errors import ConfigError
from workcell.export.errors import OutputNotEmptyError, UnknownTrialError
from workcell.record.store import Store


def _run(argv: Sequence[str]) -> int:
    parser = argparse.ArgumentParser(prog="workcell")
    subparsers = parser.add_subparsers(dest="command", required=True)
    render.register(subparsers)
    args = parser.parse_args(["render", *argv])
    status: int = args.func(args)
    return status


def test_renders_one_video_per_trial_and_camera(
    recorded: Stores, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    av = pytest.importorskip("av")
    with Store.open(recorded.short, writer=False) as store:
        trial = store.trials()[1]
    argv = ["--store", str(recorded.short), "--camera", "wrist_l_cam", "--size", "64x48"]
    argv += ["--trial", trial.trial_id, "--out", str(tmp_path)]
    assert _run(argv) == 0
    out, err = capsys.readouterr()
    video = tmp_path / f"{trial.trial_id}_wrist_l_cam.mp4"
    assert out.splitlines()[0].startswith(f"{video}: {trial.n_frames} frames, replay error ")
    assert f"trial 1/1: {trial.trial_id}, {trial.n_frames} frames, replay error " in err
    with av.open(str(video)) as container:
        frames = list(container.decode(video=0))
    assert len(frames) == trial.n_frames
    assert (frames[0].width, frames[0].height) == (64, 48)
    with pytest.raises(OutputNotEmptyError, match="exists; remove it or choose another --out"):
        _run(argv)


def test_bad_arguments_are_refused_before_any_work(recorded: Stores, tmp_path: Path) -> None:
    base = ["--store", str(recorded.short), "--out", str(tmp_path)]
    with pytest.raises(ConfigError) as error:
        _run([*base, "--camera", "tail_cam", "--size", "65x48"])
    assert len(error.value.problems) == 2
    with pytest.raises(UnknownTrialError, match="--trial abc: no such trial"):
        _run([*base, "--camera", "head_cam", "--trial", "abc"])
    assert not any(tmp_path.iterdir())
