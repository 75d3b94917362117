"""A session run headless to its end, recorded: the loop ``workcell collect`` and its
scale-out workers share.

Each pass steps the session, unless the recorder has failed (the running trial ends
``interrupted``/``storage_error``) or the caller asks to stop (it ends with the reason the
caller gives, e.g. ``application_quit`` on SIGINT); the session is recorded as
``interrupted`` when its last trial was.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from workcell.record.media_paths import media_dir_for
from workcell.recording.media import CameraOptions, MediaRecorder
from workcell.recording.recorder import Recorder, RecordingStore
from workcell.task import events as ev
from workcell.task.runner import SessionRunner

StopReason = Callable[[], ev.InterruptionReason | None]
"""Why the session must stop now (the running trial is interrupted so), or None."""


def make_recorder(
    store: RecordingStore, store_path: Path, runner: SessionRunner, cameras: CameraOptions | None
) -> Recorder:
    """A recorder of ``runner``'s session into ``store`` (at ``store_path``), with the
    ``cameras`` recorded as videos beside the store when given."""
    media = None
    if cameras is not None:
        rate = runner.config.recording.sampling_rate_hz
        media = MediaRecorder(runner.sim.world.model, cameras, media_dir_for(store_path), rate)
    return Recorder(store, runner, media=media)


def run_recorded(
    runner: SessionRunner,
    recorder: Recorder | None,
    stop: StopReason,
    after_step: Callable[[], None],
) -> bool:
    """Run ``runner``'s session to its end, recorded by ``recorder`` (None: not recorded),
    calling ``after_step`` after every pass; closes the recorder. Returns whether the
    session ended interrupted."""
    runner.start()
    while runner.current is not None:
        if recorder is not None and recorder.failure is not None:
            runner.interrupt("storage_error")
        elif (reason := stop()) is not None:
            runner.interrupt(reason)
        else:
            runner.step()
        after_step()
    interrupted = bool(runner.results) and runner.results[-1].outcome == "interrupted"
    if recorder is not None:
        recorder.close(interrupted)
    return interrupted
