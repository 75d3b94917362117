"""Hostile configuration input on the real command line (``python -m workcell`` in a
subprocess): files that are not UTF-8, numbers Python refuses to read or a float cannot
hold, rates so small their ratio overflows. Each is one line, ``workcell: error: ...``,
naming what was wrong and what is allowed, exit status 2, and nothing runs."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from workcell.study.template import TEMPLATE

DIGITS_400 = "1" + "0" * 399
DIGITS_5000 = "1" + "0" * 4999


def _workcell(*args: str, cwd: Path) -> tuple[int, list[str], str]:
    """Exit status, standard error's lines and standard output of one command."""
    done = subprocess.run(
        [sys.executable, "-m", "workcell", *args],
        check=False,
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=120,
    )
    return done.returncode, done.stderr.splitlines(), done.stdout


def _one_error(*args: str, cwd: Path) -> str:
    """The one error line of a command that must refuse its input, without its prefix."""
    code, errors, out = _workcell(*args, cwd=cwd)
    assert code == 2, errors
    assert out == ""
    assert len(errors) == 1, errors
    assert errors[0].startswith("workcell: error: "), errors
    return errors[0].removeprefix("workcell: error: ")


def _study(tmp_path: Path, session: str = "", physical: str = '"world.grasp" = "physical"') -> Path:
    text = TEMPLATE.replace("[session]\n", f"[session]\n{session}\n", 1)
    text = text.replace('"world.grasp" = "physical"', physical, 1)
    path = tmp_path / "study.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("setting", "line"),
    [
        (
            "recording.sampling_rate_hz=1e-310",
            "recording.sampling_rate_hz = 1e-310: must divide the physics rate "
            "1/world.timestep = 400 Hz into a whole number of at most 1000000 steps, e.g. ",
        ),
        (
            "world.robot.ik_hz=1e-310",
            "world.robot.ik_hz = 1e-310: must divide the control rate control_hz = 40 Hz into "
            "a whole number of at most 1000000 steps, e.g. ",
        ),
        (
            "world.robot.teleop_ik_hz=1e-310",
            "world.robot.teleop_ik_hz = 1e-310: must divide the control rate "
            "teleop_control_hz = 100 Hz into a whole number of at most 1000000 steps, e.g. ",
        ),
        (
            f"world.box.mass={DIGITS_400}",
            "world.box.mass = a 400-digit number: must be between 0.05 and 10 kg",
        ),
    ],
)
def test_a_hostile_set_is_one_error_line(tmp_path: Path, setting: str, line: str) -> None:
    assert _one_error("config", "--set", setting, cwd=tmp_path).startswith(line)


def test_a_number_python_refuses_to_read_is_one_error_line(tmp_path: Path) -> None:
    error = _one_error("config", "--set", f"seed={DIGITS_5000}", cwd=tmp_path)
    assert error.startswith("--set 'seed=100000")
    assert error.endswith(
        "... (5007 characters): a whole number of more than 4300 digits; no setting allows "
        "one of more than 19"
    )


def test_collect_refuses_a_rate_that_overflows_before_it_records(tmp_path: Path) -> None:
    error = _one_error(
        "collect", "--set", "recording.sampling_rate_hz=1e-310", "--store", "s.sqlite", cwd=tmp_path
    )
    assert error.startswith("recording.sampling_rate_hz = 1e-310: must divide")
    assert not (tmp_path / "s.sqlite").exists()


def test_a_config_file_that_is_not_utf8_is_one_error_line(tmp_path: Path) -> None:
    (tmp_path / "latin1.toml").write_bytes("operator_id = 'Jos\xe9'\n".encode("latin-1"))
    assert _one_error("config", "--config", "latin1.toml", cwd=tmp_path) == (
        "config file 'latin1.toml' is not UTF-8 text: byte 0xe9 at offset 18"
    )


def test_a_config_file_with_a_number_python_refuses_names_its_line(tmp_path: Path) -> None:
    (tmp_path / "long.toml").write_text(f"[world.box]\nmass = {DIGITS_5000}\n")
    assert _one_error("config", "--config", "long.toml", cwd=tmp_path) == (
        "config file 'long.toml' is not valid TOML: line 2, world.box.mass: a whole number of "
        "more than 4300 digits; no setting allows one of more than 19"
    )


def test_a_study_file_that_is_not_utf8_is_one_error_line(tmp_path: Path) -> None:
    path = _study(tmp_path)
    path.write_bytes(path.read_bytes() + b"# \xff\n")
    error = _one_error("study", "study.toml", cwd=tmp_path)
    assert error.startswith("study file 'study.toml' is not UTF-8 text: byte 0xff at offset ")


def test_a_missing_study_file_is_called_a_study_file(tmp_path: Path) -> None:
    assert _one_error("study", "nothing.toml", cwd=tmp_path) == (
        "study file 'nothing.toml' does not exist"
    )


def test_a_400_digit_number_in_a_condition_names_the_condition(tmp_path: Path) -> None:
    _study(tmp_path, physical=f'"world.box.mass" = {DIGITS_400}')
    assert _one_error("study", "study.toml", cwd=tmp_path) == (
        "study.toml: conditions[2].settings.world.box.mass = a 400-digit number: must be "
        "between 0.05 and 10 kg"
    )


def test_a_rate_that_overflows_in_the_study_session_is_one_line(tmp_path: Path) -> None:
    _study(tmp_path, session="recording.sampling_rate_hz = 1e-310")
    error = _one_error("study", "study.toml", cwd=tmp_path)
    assert error.startswith(
        "study.toml: session.recording.sampling_rate_hz = 1e-310: must divide the physics rate"
    )


def test_a_typo_in_the_study_session_is_reported_once_as_the_sessions(tmp_path: Path) -> None:
    _study(tmp_path, session='world.grsap = "physical"')
    assert _one_error("study", "study.toml", cwd=tmp_path) == (
        "study.toml: session.world.grsap: unknown setting; allowed here: conveyor, feeder, box, "
        "target, robot, randomization, grasp, timestep"
    )


def test_a_value_where_a_flag_needs_a_section_is_one_error_line(tmp_path: Path) -> None:
    (tmp_path / "flat.toml").write_text("task = 3\n")
    error = _one_error("collect", "--config", "flat.toml", "--mode", "collection", cwd=tmp_path)
    assert error == "task = 3: must be a [task] section"


def test_a_frame_rate_too_fast_for_a_video_is_refused_before_recording(tmp_path: Path) -> None:
    """--cameras records one video frame per recorded frame: a rate the video encoder
    refuses is a bad setting, not an error once the first trial's video starts (which left
    the session and its trial open in the store)."""
    error = _one_error(
        "collect",
        *("--cameras", "head_cam", "--set", "recording.sampling_rate_hz=400"),
        *("--store", "s.sqlite"),
        cwd=tmp_path,
    )
    assert error == (
        "recording.sampling_rate_hz = 400: --cameras records a video frame per recorded "
        "frame: must be between 1 and 240 Hz"
    )
    assert not (tmp_path / "s.sqlite").exists()


def test_a_flag_given_thousands_of_digits_is_one_short_error_line(tmp_path: Path) -> None:
    error = _one_error("collect", "--seed", DIGITS_5000, "--no-store", cwd=tmp_path)
    assert error.startswith("argument --seed: invalid int value: '10000")
    assert error.endswith("... (5002 characters) (see 'workcell collect --help')")
    assert len(error) < 200
