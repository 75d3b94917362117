"""The recorder's store when frames are written in the recording process itself.

:class:`InProcessStore` is a :class:`~workcell.record.store.Store` that also takes frames
as captured during recording (:mod:`workcell.recording.frame_capture`) and formats them
into the store's frame batches here (:mod:`workcell.recording.frame_format`); a
:class:`~workcell.recording.store_process.StoreProcess` does the same in a writer process.
"""

from __future__ import annotations

from workcell.record.store import Store
from workcell.recording.frame_capture import CapturedFrames, FrameLayout
from workcell.recording.frame_format import FrameFormatter


class InProcessStore(Store):
    """A store opened for writing (use :meth:`Store.open`) that records captured frames."""

    _formatter: FrameFormatter | None = None

    def prepare_frames(self, layout: FrameLayout) -> None:
        """Nothing to prepare in-process (a :class:`~workcell.recording.store_process.
        StoreProcess` makes its frame ring here)."""

    def add_captured_frames(self, trial_id: str, frames: CapturedFrames) -> int:
        """Append captured frames to a running trial, formatted into the frame columns
        here; as :meth:`Store.add_frames`."""
        if self._formatter is None:
            self._formatter = FrameFormatter()
        session_id, first_index = self.next_frame(trial_id)
        batch = self._formatter.batch(frames, session_id, trial_id, first_index)
        return self.add_frames(trial_id, batch)

    def failure_pending(self) -> bool:
        """False: in-process, a failure is raised by the call that met it."""
        return False

    def trial_end_written(self, trial_id: str) -> bool:
        """True: in-process, :meth:`Store.end_trial` has written the end (or raised)
        before it returns."""
        return True
