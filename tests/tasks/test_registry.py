"""Finding tasks: by name, by ``module:Class``, and one clear error for anything else."""

from __future__ import annotations

import pytest

from tests.tasks.external_task import CarefulTransfer
from workcell.cli.main import main
from workcell.errors import ConfigError
from workcell.session.config import TaskConfig
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.registry import BUILT_IN, DEFAULT_TASK, load_task, recorded_task, task_class


def test_the_built_in_tasks_are_found_by_name() -> None:
    assert DEFAULT_TASK == TaskConfig().kind == "box_transfer"
    assert BUILT_IN["box_transfer"] is BoxTransfer
    task = load_task("box_transfer")
    assert isinstance(task, BoxTransfer)
    assert task.stages[0] == "none" and task.stages[-1] == "delivered"
    assert set(task.worlds) == {"D0", "D1", "D2"}


def test_a_task_of_ones_own_loads_from_module_and_class() -> None:
    kind = "tests.tasks.external_task:CarefulTransfer"
    assert task_class(kind) is CarefulTransfer
    assert load_task(kind).instruction(2) == "Please carry 2 box(es) to the table, gently."
    assert TaskConfig(kind=kind).kind == kind


@pytest.mark.parametrize(
    ("kind", "says"),
    [
        ("conveyor_dance", "no such task; the tasks are box_transfer, "),
        ("tests.tasks.no_such_module:Task", "cannot import tests.tasks.no_such_module"),
        ("tests.tasks.external_task:Missing", "has no subclass of workcell.tasks.Task named"),
        ("tests.tasks.external_task:NotATask", "has no subclass of workcell.tasks.Task named"),
    ],
)
def test_anything_else_is_one_clear_error(kind: str, says: str) -> None:
    with pytest.raises(ConfigError) as raised:
        load_task(kind)
    (problem,) = raised.value.problems
    assert problem.startswith(f"task.kind = {kind!r}: ") and says in problem


def test_a_kind_that_is_neither_a_name_nor_module_class_is_refused_as_a_setting() -> None:
    for kind in ("Box Transfer", "a:b:c", "", "x" * 65):
        with pytest.raises(ConfigError, match=r"task\.kind = .*module:Class"):
            TaskConfig(kind=kind)


def test_a_recorded_session_names_its_task_or_ran_box_transfer() -> None:
    assert isinstance(recorded_task({}), BoxTransfer)
    assert isinstance(recorded_task({"task": {"mode": "practice"}}), BoxTransfer)
    kind = "tests.tasks.external_task:CarefulTransfer"
    assert isinstance(recorded_task({"task": {"kind": kind}}), CarefulTransfer)


def test_workcell_tasks_lists_each_task_on_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["tasks"]) == 0
    lines = capsys.readouterr().out.splitlines()
    (line,) = [n for n in lines if n.startswith("box_transfer ")]
    assert "conveyor" in line
    assert line.endswith("stages: none > touched > grasped > lifted > over_zone > delivered")
    assert "worlds (--world): D0, D1, D2" in lines[-1]
    assert main(["tasks", "tests.tasks.external_task:CarefulTransfer"]) == 0
    assert capsys.readouterr().out.startswith("careful_transfer  box transfer, asked politely")
    assert main(["tasks", "nowhere:Task"]) == 2
    assert "tasks = 'nowhere:Task': cannot import nowhere" in capsys.readouterr().err
