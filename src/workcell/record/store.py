"""The store: one SQLite file (WAL mode) holding sessions, trials, events, frames and
annotations, linked by foreign keys, every row with a content checksum, each session's
rows chained by hashes (:mod:`workcell.record.chain`).

Durability contract: frames are appended with :meth:`Store.add_frames` and made durable by
:meth:`Store.commit`. A committed batch survives the death of the recording process
(SIGKILL included): the next writer to open the store finds it intact and closes the trial
as ``interrupted``/``crash_recovered``. The recorder commits every 5 frames (0.25 s at
20 Hz), so a crash loses at most 0.25 s. Every other write method commits at once,
pending frames included. A power cut of the whole machine can lose the commits since the
log was last synced (``synchronous=NORMAL``), never corrupt earlier ones; the end of a
trial and of a session are synced as they commit (see :mod:`workcell.record.writes`), so
every trial closed before a power cut is kept whole.

A failed write (disk full, file-size limit, I/O error) rolls its transaction back, raises
:class:`StorageError` with one line naming the store and the cause, and stops the store
from recording; :meth:`Store.try_interrupt_session` then closes the session's trial as
``storage_error`` and the session, into the room the writer keeps free for it
(:mod:`workcell.record.reserve`). Data committed before is never touched.

A Store is used from one thread.
"""

from __future__ import annotations

import contextlib
import os
import sqlite3
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Self

from workcell.closing import Closing
from workcell.metrics import FrameArrays, MetricThresholds, compute_trial_metrics
from workcell.record import chain, chain_tip, lifecycle, rowio
from workcell.record.annotations import annotation_row
from workcell.record.batch import RowBatch
from workcell.record.chain import ChainKey
from workcell.record.columns import INTERRUPTION_REASONS
from workcell.record.connection import WriterLock, connect
from workcell.record.entries import SessionInfo, StoredMetrics, TrialEnd, TrialStart
from workcell.record.errors import RecordError, StoreError
from workcell.record.failure import close_after_failure
from workcell.record.frame_blocks import BLOCK_REALS, write_block
from workcell.record.ids import new_id
from workcell.record.reading import StoreReading
from workcell.record.recovery import KnownEnd, recover_with_headroom
from workcell.record.reserve import Reserve
from workcell.record.running import (
    Running,
    end_columns,
    frame_batch,
    session_row,
    trial_row,
)
from workcell.record.schema import ANNOTATIONS
from workcell.record.writes import WriteGuard

CLOSING_STATUSES = ("completed", "interrupted")


class Store(StoreReading, Closing):
    """A store file opened for reading or for writing; use :meth:`open`."""

    def __init__(
        self,
        path: Path,
        conn: sqlite3.Connection,
        lock: WriterLock | None,
        key: ChainKey | None = None,
    ) -> None:
        self.path = path
        self._conn = conn
        self._lock = lock
        self._key = key
        self._reserve = Reserve(path)
        self._sessions: dict[str, Running] = {}
        self._trials: dict[str, Running] = {}
        self._guard = WriteGuard(path, conn, self._resync) if lock is not None else None
        self.recovered: tuple[str, ...] = ()
        """Trials crash recovery closed when this writer opened the store."""
        self._opened = False
        """Whether :meth:`open` finished (recovery included)."""

    @classmethod
    def open(
        cls,
        path: str | os.PathLike[str],
        *,
        writer: bool,
        key: ChainKey | None = None,
        known: Mapping[str, KnownEnd] | None = None,
        check: bool | None = None,
    ) -> Self:
        """Open (a writer also creates or migrates) the store at ``path``.

        ``check`` (default: for a writer) runs SQLite's quick integrity check first, so
        that a damaged file is refused with a :class:`StoreError` instead of being read
        or written into.

        A writer takes the store's writer lock, keeps the headroom file beside it, signs
        the chain links it writes with ``key`` (if given), and recovers what a dead writer
        left open (sessions in ``known`` with the reason given there), signing what it
        closes only when the store's chain tip is signed with ``key``. Raises
        :class:`StoreError` for a missing file (reader), a file that is not a store, a
        store of a newer schema, a store another process is writing, or (writer) a store
        whose chain tip shows that links were deleted or the tip rewritten;
        :class:`StorageError` when the disk has no room for a writer.
        """
        path = Path(path)
        check = writer if check is None else check
        if not writer:
            return cls(path, connect(path, writer=False, check=check), None)
        lock = WriterLock(path)
        try:
            no_room = Reserve(path).missing_room()
            if no_room is not None and not path.exists():
                raise no_room  # nothing to recover: refuse before creating anything
            store = cls(path, connect(path, writer=True, check=check, key=key), lock, key)
        except BaseException:
            lock.release()
            raise
        try:
            vouched = chain_tip.writer_check(store._conn, path, key)
            store.recovered = recover_with_headroom(  # signed only where the key vouches
                store._conn, store._reserve, key=key if vouched else None, known=known or {}
            )
            if no_room is not None or not store._reserve.path.exists():
                store._reserve.ensure()  # raises: the disk is still full
        except BaseException:
            store.close()
            raise
        store._opened = True
        return store

    @property
    def writer(self) -> bool:
        return self._lock is not None

    def close(self) -> None:
        """Commit pending frames and close. Trials still running stay open in the file;
        the next writer recovers them, in the headroom file kept for that. A writer that
        leaves nothing open removes the headroom and lock files: the next writer makes
        them again (and is refused at once if the disk has no room for the headroom)."""
        with contextlib.suppress(sqlite3.Error, StoreError):
            if self._guard is not None and self._guard.failure is None:
                self._guard.commit()
        self._conn.close()
        self._guard = None
        if self._lock is not None:
            if self._opened and not self._sessions:  # nothing left for the next to close
                self._reserve.release()
            self._lock.release()  # and its file
            self._lock = None

    # ------------------------------------------------------------------ writing

    def create_session(self, info: SessionInfo) -> str:
        """Record a new session (status ``running``); returns its id."""
        session_id = new_id()
        batch = session_row(session_id, info)
        with self._write() as conn:
            rowio.insert(conn, batch)
            chain.link_start(conn, session_id, batch.checksums()[0], self._key)
        self._sessions[session_id] = Running(session_id)
        return session_id

    def start_trial(
        self, session_id: str, start: TrialStart, *, trial_id: str | None = None
    ) -> str:
        """Record a new trial of a running session (its next trial_index); returns its id
        (``trial_id`` if given: a fresh :func:`~workcell.record.ids.new_id` of the caller)."""
        session = self._running_session(session_id)
        if session.trial_id is not None:
            raise RecordError(f"trial {session.trial_id} is still running: end it first")
        trial_id = trial_id or new_id()
        batch = trial_row(session_id, trial_id, session.next_index, start)
        # known before it is written: a failure writing it closes it as interrupted
        session.next_index += 1
        session.trial_id = trial_id
        self._trials[trial_id] = Running(session_id, start_row=batch)
        with self._write() as conn:
            rowio.insert(conn, batch)
        return trial_id

    def add_event(
        self,
        session_id: str,
        kind: str,
        payload: Mapping[str, object] | None = None,
        *,
        trial_id: str | None = None,
        t_sim: float | None = None,
        t_wall: float | None = None,
    ) -> str:
        """Record an event of a running session (and of its running trial, if given);
        returns its id. ``t_wall`` defaults to now."""
        session = self._running_session(session_id)
        if trial_id is not None and self._running_trial(trial_id).session_id != session_id:
            raise RecordError(f"trial {trial_id} is not a trial of session {session_id}")
        if not kind:
            raise RecordError("event kind: must be a non-empty text")
        event_id = new_id()
        with self._write() as conn:
            lifecycle.insert_event(
                conn,
                event_id=event_id,
                session_id=session_id,
                trial_id=trial_id,
                seq=session.next_seq,
                kind=kind,
                payload=payload or {},
                t_sim=t_sim,
                t_wall=time.time() if t_wall is None else t_wall,
            )
        session.next_seq += 1
        return event_id

    def add_frames(self, trial_id: str, frames: RowBatch) -> int:
        """Append frames to a running trial (not yet durable: call :meth:`commit`).

        ``frames`` is a batch of the frames layout (:data:`~workcell.record.schema.FRAMES`)
        with the trial's ``session_id`` and ``trial_id`` and ``frame_index`` continuing the
        trial's frames in steps of 1 (see :meth:`next_frame`); build one from rows or
        columns with :meth:`RowBatch.from_mappings` / :meth:`RowBatch.from_columns`.
        NULL (None or NaN) is legitimate in the device columns only; elsewhere it is
        stored as given and reported by ``workcell verify``. Returns the number added.
        """
        trial = self._running_trial(trial_id)
        batch = frame_batch(frames, trial, trial_id)
        n = len(batch)
        if n:
            with self._write(commit=False) as conn:
                rowio.insert(conn, batch)
            trial.next_index += n
            trial.metric_rows.append(batch.real[:, BLOCK_REALS])
        return n

    def next_frame(self, trial_id: str) -> tuple[str, int]:
        """Of a running trial: its session id and the ``frame_index`` its next frame takes."""
        trial = self._running_trial(trial_id)
        return trial.session_id, trial.next_index

    def commit(self) -> None:
        """Make everything added so far durable against the death of this process."""
        self._writable().commit()

    def end_trial(
        self, trial_id: str, end: TrialEnd, *, thresholds: MetricThresholds | None = None
    ) -> None:
        """Close a running trial: its outcome, metrics, frame count and checksums.

        With ``thresholds``, the metrics stored are computed here from the trial's frames
        as stored (``end.metrics`` is ignored)."""
        trial = self._running_trial(trial_id)
        matrix = trial.metric_matrix()
        m = end.metrics
        if thresholds is not None:
            frames = FrameArrays.from_matrix(matrix)
            m = StoredMetrics.of(
                compute_trial_metrics(frames, end.outcome == "success", thresholds)
            )
        changes = end_columns(end, m)
        with self._write(durable=True) as conn:
            lifecycle.close_trial(conn, trial_id, changes)
            write_block(conn, trial_id, matrix)
            chain.link_trial(conn, trial_id, self._key)
        self._forget_trial(trial_id, trial)

    def end_session(self, session_id: str, status: str = "completed") -> None:
        """Close a running session (``completed`` or ``interrupted``); end its trial first."""
        session = self._running_session(session_id)
        if status not in CLOSING_STATUSES:
            raise RecordError(f"session status {status!r}: must be one of {CLOSING_STATUSES}")
        if session.trial_id is not None:
            raise RecordError(f"trial {session.trial_id} is still running: end it first")
        with self._write(durable=True) as conn:
            lifecycle.close_session(conn, session_id, status, time.time(), self._key)
        del self._sessions[session_id]

    def annotate(self, trial_id: str, kind: str, reason: str, by: str) -> str:
        """Record a reviewer's decision on a trial (who, when, why); returns its id. Raw
        rows are never rewritten."""
        row = annotation_row(trial_id, kind, reason, by)
        with self._write(durable=True) as conn:
            if conn.execute("SELECT 1 FROM trials WHERE trial_id = ?", (trial_id,)).fetchone():
                rowio.insert(conn, RowBatch.from_mappings(ANNOTATIONS, [row]))
            else:
                raise RecordError(f"no trial {trial_id} in store {self.path}")
        return str(row["annotation_id"])

    def try_mark_interrupted(self, trial_id: str, reason: str = "storage_error") -> bool:
        """:meth:`try_interrupt_session` for the session of a running trial; False when
        the trial is not running here."""
        trial = self._trials.get(trial_id)
        if trial is None:
            return False
        return self.try_interrupt_session(trial.session_id, reason)

    def try_interrupt_session(self, session_id: str, reason: str = "storage_error") -> bool:
        """Best effort after a failure: close the session's running trial as interrupted
        (``reason``, with an event naming the error) and the session as ``interrupted``.
        Returns whether it was written; never raises for storage trouble (the next writer
        recovers what is left open)."""
        if reason not in INTERRUPTION_REASONS:
            raise RecordError(f"reason {reason!r}: must be one of {INTERRUPTION_REASONS}")
        if self._guard is None or session_id not in self._sessions:
            return False
        started = {
            trial_id: trial.start_row
            for trial_id, trial in self._trials.items()
            if trial.session_id == session_id and trial.start_row is not None
        }
        if not close_after_failure(
            self._conn,
            guard=self._guard,
            reserve=self._reserve,
            session_id=session_id,
            started=started,
            reason=reason,
            key=self._key,
        ):
            return False
        for trial_id, trial in list(self._trials.items()):
            if trial.session_id == session_id:
                del self._trials[trial_id]
        del self._sessions[session_id]
        return True

    # ------------------------------------------------------------------ internals

    def _running_session(self, session_id: str) -> Running:
        self._writable()
        try:
            return self._sessions[session_id]
        except KeyError:
            raise RecordError(
                f"session {session_id} is not running in this store: create it first"
            ) from None

    def _running_trial(self, trial_id: str) -> Running:
        self._writable()
        try:
            return self._trials[trial_id]
        except KeyError:
            raise RecordError(
                f"trial {trial_id} is not running in this store: start it first"
            ) from None

    def _forget_trial(self, trial_id: str, trial: Running) -> None:
        del self._trials[trial_id]
        self._sessions[trial.session_id].trial_id = None

    def _writable(self) -> WriteGuard:
        if self._guard is None:
            raise StoreError(
                f"store {self.path} is open for reading (or closed): open it as writer"
            )
        self._guard.require()
        return self._guard

    def _write(
        self, *, commit: bool = True, durable: bool = False
    ) -> contextlib.AbstractContextManager[sqlite3.Connection]:
        return self._writable().write(commit=commit, durable=durable)

    def _resync(self) -> None:
        """After a rollback: counters from what is committed."""
        for trial_id, trial in self._trials.items():
            (trial.next_index,) = self._conn.execute(
                "SELECT count(*) FROM frames WHERE trial_id = ?", (trial_id,)
            ).fetchone()
            trial.metric_rows = [trial.metric_matrix()]
        for session_id, session in self._sessions.items():
            session.next_seq = lifecycle.next_seq(self._conn, session_id)
