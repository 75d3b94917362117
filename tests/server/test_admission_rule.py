"""The admission rule by measured headroom (:mod:`workcell.server.admission`) on figures,
and the admin page's warning in words."""

from __future__ import annotations

from workcell.server.admission import AdmissionRule, Measured, behind_real_time


def test_nothing_running_is_always_admitted() -> None:
    assert AdmissionRule(cores=0.01).refuses([]) is None


def test_one_more_fits_when_every_session_keeps_real_time_and_the_cores_suffice() -> None:
    rule = AdmissionRule(cores=2.0)
    assert rule.refuses([Measured(1.0, 0.6)]) is None  # 2 x 0.6 = 1.2 cores of 2
    why = rule.refuses([Measured(1.0, 0.6), Measured(0.99, 0.7)])  # 3 x 0.65 = 1.95
    assert why is None
    why = rule.refuses([Measured(1.0, 0.8), Measured(1.0, 0.8)])  # 3 x 0.8 = 2.4 > 2
    assert why == "3 sessions at 0.80 cores each need 2.40 cores; this machine gives the sessions 2"


def test_a_session_below_the_real_time_needed_keeps_the_next_waiting() -> None:
    rule = AdmissionRule(cores=16.0)
    why = rule.refuses([Measured(1.0, 0.5), Measured(0.91, 0.5), Measured(0.97, 0.5)])
    assert why == (
        "2 running session(s) at 0.91x real time, below the 0.98x needed to start one more"
    )
    assert AdmissionRule(16.0, min_real_time_factor=0.9).refuses([Measured(0.91, 0.5)]) is None


def test_a_session_not_yet_measured_counts_at_one_core() -> None:
    assert AdmissionRule(cores=2.0).refuses([None]) is None  # 2 x 1 core
    assert AdmissionRule(cores=1.5).refuses([None]) == (
        "2 sessions at 1.00 cores each (assumed until a session is measured) need 2.00 "
        "cores; this machine gives the sessions 1.5"
    )
    # once one is measured, its figure stands for the others too
    assert AdmissionRule(cores=1.5).refuses([None, Measured(1.0, 0.4)]) is None


def test_the_admin_page_warns_in_words_when_sessions_fall_behind() -> None:
    assert behind_real_time([1.0, 0.97]) == ""
    assert behind_real_time([0.0]) == ""  # not yet measured
    assert behind_real_time([0.85, 0.88, 1.0]) == (
        "2 sessions are running at 0.85x real time: trials are flagged sampling_gap; "
        "stop or pause a session, or run fewer at once"
    )
    assert behind_real_time([0.9]).startswith("1 session is running at 0.90x real time")
