"""The record is readable without the physics engine: importing the store, exporting a
store to CSV and auditing that export load no MuJoCo (nor the simulation, control or
recording packages). Each is checked in a fresh interpreter, since this one has MuJoCo
loaded already."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from tests.record import synthetic

PHYSICS = ("mujoco", "workcell.sim.world", "workcell.control", "workcell.recording")
"""Modules none of these paths may load (the physics engine and what is built on it)."""


def _loaded_after(code: str, *args: str) -> set[str]:
    """The modules a fresh interpreter holds after running ``code``."""
    script = textwrap.dedent(code) + "\nimport sys\nprint('\\n'.join(sorted(sys.modules)))\n"
    done = subprocess.run(
        [sys.executable, "-c", script, *args],
        check=False,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    return set(done.stdout.split())


def _physics(modules: set[str]) -> list[str]:
    return sorted(m for m in modules if any(m == p or m.startswith(f"{p}.") for p in PHYSICS))


@pytest.fixture(scope="module")
def csv_export(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("no-physics")
    synthetic.fill_store(folder / "s.sqlite")
    out = folder / "csv"
    modules = _loaded_after(
        """
        import sys
        from workcell.record.export_csv import export_csv
        export_csv(sys.argv[1], sys.argv[2])
        """,
        str(folder / "s.sqlite"),
        str(out),
    )
    assert _physics(modules) == [], "the CSV export loads the physics engine"
    return out


def test_importing_the_store_loads_no_physics() -> None:
    modules = _loaded_after(
        """
        import workcell.record
        from workcell.record import Store
        import workcell.record.columns, workcell.record.verify, workcell.record.merge
        """
    )
    assert "workcell.record.store" in modules
    assert _physics(modules) == []


def test_exporting_and_auditing_a_csv_export_loads_no_physics(csv_export: Path) -> None:
    assert (csv_export / "frames.csv").is_file()  # the export ran (in its own interpreter)
    modules = _loaded_after(
        """
        import sys
        from pathlib import Path
        from workcell.audit.csv_source import CsvSource
        from workcell.audit.run import run_audit
        result = run_audit(CsvSource(Path(sys.argv[1])))
        assert len(result.trials) == 4, result.trials
        """,
        str(csv_export),
    )
    assert "workcell.audit.run" in modules
    assert _physics(modules) == []


def test_the_check_sees_the_physics_engine_where_it_is_loaded() -> None:
    modules = _loaded_after("import workcell.recording.frame_capture")
    assert "mujoco" in _physics(modules)
