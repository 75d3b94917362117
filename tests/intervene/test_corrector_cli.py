"""``workcell collect --corrector expert``: the scripted corrector watches a headless
session, and bad values are refused before anything runs, one line each."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from workcell.cli.main import main
from workcell.record.store import Store


def test_collect_with_a_corrector_records_its_corrections_as_a_live_session(
    tmp_path: Path,
) -> None:
    store = tmp_path / "c.sqlite"
    # the expert at skill 0 still waits for the box to settle on the belt: it stalls at none
    args = ["collect", "--mode", "collection", "--trials", "1", "--skill", "0", "--corrector",
            "expert", "--stall-s", "0.5", "--set", "task.time_limit_s=3", "--set",
            "task.countdown_s=0", "--writer", "inline", "--store", str(store)]  # fmt: skip
    assert main(args) == 0
    with Store.open(store, writer=False) as reader:
        (trial,) = reader.trials()
        flags = np.asarray(reader.frames(trial.trial_id)["intervention"])
        switches = [
            (e.kind, e.payload["reason"], e.payload["operator_id"])
            for e in reader.events(trial.trial_id)
            if e.kind in ("take_over", "hand_back")
        ]
    assert trial.driver == "expert"
    assert switches[0] == ("take_over", "stalled 0.5 s at none", "expert")
    assert flags[0] == 0.0 and flags[-1] == 1.0  # the corrector still drives at the end
    # the audit counts the corrections as the corrector's, as a watching person's
    out = tmp_path / "audit"
    assert main(["audit", "--store", str(store), "--out", str(out)]) == 0
    groups = json.loads((out / "summary.json").read_text())["interventions"]["groups"]
    watched = {(g["driver"], g["person"]): g["take_overs"] for g in groups}
    assert watched == {("expert", ""): 1, ("expert", "expert"): 1}


@pytest.mark.parametrize(
    ("args", "error"),
    [
        (["--corrector", "person"], "--corrector: invalid choice: 'person' (choose from 'expert')"),
        (["--stall-s", "2"], "--stall-s: the corrector's rule; it needs --corrector expert"),
        (
            ["--corrector", "expert", "--stall-s", "0"],
            "--stall-s = 0: must be 0.1 to 3600 seconds",
        ),
        (
            ["--corrector", "expert", "--workers", "2"],
            "--corrector: watches the session in this process; drop --workers/--ray",
        ),
    ],
)
def test_bad_corrector_options_are_refused_in_one_line(
    args: list[str], error: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["collect", "--no-store", *args]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert error in captured.err
