"""A recording process for the fault tests: run as ``python -m tests.record.writer_process``.

It opens a store, records ``--complete`` finished trials, then starts one more trial and
appends synthetic frames in batches (one batch = 0.25 s at 20 Hz), committing each batch
and then printing the trial's committed frame count (flushed), until ``--frames`` frames,
a signal, or a storage error:

- SIGINT / SIGTERM: the trial ends as interrupted (application_quit), the session as
  interrupted; exit 0.
- StorageError: its one-line message goes to stderr, the trial is marked interrupted
  (storage_error) when possible; exit 1.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence

from tests.record import synthetic
from workcell.record import StorageError, Store, TrialEnd
from workcell.recording.shutdown import ShutdownSignals

EXIT_STORAGE_ERROR = 1


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--store", required=True)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--batch", type=int, default=5)
    parser.add_argument("--pause", type=float, default=0.0, help="seconds between batches")
    parser.add_argument("--frames", type=int, default=10**9, help="stop after this many")
    parser.add_argument("--complete", type=int, default=0, help="finished trials first")
    parser.add_argument("--complete-frames", type=int, default=20)
    args = parser.parse_args(argv)

    with Store.open(args.store, writer=True) as store, ShutdownSignals() as shutdown:
        session_id = store.create_session(synthetic.session_info(args.seed))
        for k in range(args.complete):
            trial_id = store.start_trial(session_id, synthetic.trial_start(k))
            store.add_frames(
                trial_id,
                synthetic.batch(
                    store, trial_id, synthetic.frames(0, args.complete_frames, args.seed + k)
                ),
            )
            store.end_trial(trial_id, synthetic.trial_end(args.complete_frames))
        trial_id = store.start_trial(session_id, synthetic.trial_start(args.complete))
        seed = args.seed + args.complete
        count = 0
        try:
            while shutdown.requested is None and count < args.frames:
                store.add_frames(
                    trial_id,
                    synthetic.batch(store, trial_id, synthetic.frames(count, args.batch, seed)),
                )
                store.commit()
                count += args.batch
                print(count, flush=True)
                if args.pause:
                    time.sleep(args.pause)
        except StorageError as error:
            print(error, file=sys.stderr, flush=True)
            store.try_mark_interrupted(trial_id, "storage_error")
            return EXIT_STORAGE_ERROR
        end = TrialEnd(
            outcome="interrupted" if shutdown.requested else "success",
            interruption_reason="application_quit" if shutdown.requested else None,
            elapsed_s=count / synthetic.RATE_HZ,
            boxes_delivered=0,
            score=0,
        )
        store.end_trial(trial_id, end)
        store.end_session(session_id, "interrupted" if shutdown.requested else "completed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
