"""Sampling gaps, non-monotonic clocks and non-finite data are found and located."""

from __future__ import annotations

import numpy as np

from tests.audit import builders as b
from tests.audit.conftest import ExpertStores
from workcell.audit.flags import NON_MONOTONIC, NONFINITE, SAMPLING_GAP
from workcell.audit.nonfinite import NonfiniteParams, detect_nonfinite
from workcell.audit.sampling import SamplingParams, detect_sampling
from workcell.metrics import MetricThresholds, compute_trial_metrics
from workcell.record import Store


def _expert(stores: ExpertStores) -> b.Columns:
    with Store.open(stores.skilled, writer=False) as store:
        return b.columns(store, store.trials()[0].trial_id)


def test_a_clean_expert_trial_has_no_sampling_flag(expert_stores: ExpertStores) -> None:
    assert detect_sampling(b.frame_arrays(_expert(expert_stores)), 20.0, SamplingParams()) == []


def test_an_injected_one_second_gap_is_found(expert_stores: ExpertStores) -> None:
    frames = b.frame_arrays(b.with_gap(_expert(expert_stores), 150, 1.0))
    (flag,) = detect_sampling(frames, 20.0, SamplingParams())
    assert flag.name == SAMPLING_GAP
    assert not flag.disqualifying
    assert "t_wall: 1 gap(s), largest 1.050 s before frame 150" in flag.detail
    assert "t_sim: 1 gap(s), largest 1.050 s before frame 150" in flag.detail
    assert "limit 0.250 s = 5 periods" in flag.detail


def test_a_stalled_machine_is_no_gap_in_a_headless_run(expert_stores: ExpertStores) -> None:
    """At full speed the sim clock runs ahead of the wall clock; a pause of the machine
    (a wall-clock gap) is no pause in the demonstration. Real time, the same pause is."""
    columns = _expert(expert_stores)
    headless = dict(columns)
    headless["t_wall"] = columns["t_wall"][0] + columns["t_sim"] / 30  # 30x real time
    headless["t_wall"][150:] += 0.6  # the machine paused for 0.6 s
    assert detect_sampling(b.frame_arrays(headless), 20.0, SamplingParams()) == []
    paced = dict(columns)
    paced["t_wall"] = columns["t_wall"].copy()
    paced["t_wall"][150:] += 0.6
    (flag,) = detect_sampling(b.frame_arrays(paced), 20.0, SamplingParams())
    assert flag.detail.startswith("t_wall: 1 gap(s), largest 0.650 s before frame 150")
    dropped = b.frame_arrays(b.with_gap(headless, 200, 1.0))  # frames lost on the sim clock
    (flag,) = detect_sampling(dropped, 20.0, SamplingParams())
    assert flag.detail.startswith("t_sim: 1 gap(s)")


def test_a_headless_run_slowed_to_real_time_by_a_busy_machine_stays_headless(
    expert_stores: ExpertStores,
) -> None:
    """Fast at first, then as slow as real time with a 2 s pause of the machine: overall
    as slow as a paced session (sampling definition 2 flagged the pause), but its sim
    clock ran ahead of the wall clock, which a paced session never does."""
    columns = _expert(expert_stores)
    since = columns["t_sim"] - columns["t_sim"][0]
    busy_from = since[100]
    wall = np.where(since <= busy_from, since / 10, busy_from / 10 + (since - busy_from) / 0.9)
    wall[300:] += 2.0
    loaded = dict(columns)
    loaded["t_wall"] = columns["t_wall"][0] + wall
    assert wall[-1] / since[-1] > 0.9  # overall: slower than real time
    assert detect_sampling(b.frame_arrays(loaded), 20.0, SamplingParams()) == []
    strict = SamplingParams(ahead_tolerance_s=busy_from)  # would not tell it from pacing
    (flag,) = detect_sampling(b.frame_arrays(loaded), 20.0, strict)
    assert flag.detail.startswith("t_wall: 1 gap(s), largest 2.05")


def test_gaps_just_under_the_limit_are_not_flagged(expert_stores: ExpertStores) -> None:
    frames = b.frame_arrays(b.with_gap(_expert(expert_stores), 150, 0.19))
    assert detect_sampling(frames, 20.0, SamplingParams()) == []  # 0.24 s on the sim clock


def test_timestamps_that_do_not_increase_are_located(expert_stores: ExpertStores) -> None:
    columns = _expert(expert_stores)
    columns["t_wall"][40] = columns["t_wall"][39]
    flags = detect_sampling(b.frame_arrays(columns), 20.0, SamplingParams())
    assert [f.name for f in flags] == [NON_MONOTONIC]
    assert flags[0].detail == "t_wall does not increase at frame 40"
    assert flags[0].disqualifying


def test_non_finite_values_are_counted(expert_stores: ExpertStores) -> None:
    columns = _expert(expert_stores)
    columns["q_arm_l_3"][[10, 11]] = np.nan
    columns["grip_r"][11] = np.inf
    frames = b.frame_arrays(columns)
    metrics = compute_trial_metrics(frames, True, MetricThresholds())
    flag = detect_nonfinite(metrics, NonfiniteParams())
    assert flag is not None and flag.name == NONFINITE
    assert flag.detail.startswith(f"2 of {len(frames)} frames ")
    clean = compute_trial_metrics(b.frame_arrays(_expert(expert_stores)), True, MetricThresholds())
    assert detect_nonfinite(clean, NonfiniteParams()) is None
