"""Where the sessions of a server with several seats record: each session into a shard of
its own beside the store (one writer per store file), merged into the store when the
session ends.

A shard is ``<store>.live/<random>.sqlite``. Merging copies its rows verbatim (hash-chain
links included) after verifying the shard, then deletes it; a shard whose merge failed
(the store is another process's, the disk is full) stays where it is and is merged when
the server next starts, after recovering any trial a killed process left open.
"""

from __future__ import annotations

import glob
import logging
import secrets
import shutil
import threading
from pathlib import Path

from workcell.record.chain import ChainKey
from workcell.record.errors import StoreError
from workcell.record.media_paths import media_dir_for
from workcell.record.merge import MergeReport, merge_stores

logger = logging.getLogger(__name__)


def shard_folder(store: Path) -> Path:
    return store.with_name(store.name + ".live")


class SessionShards:
    """The shards of one store (thread-safe: merges run one at a time)."""

    def __init__(self, store: Path, key_file: Path | None = None) -> None:
        self.store = store
        self.key = None if key_file is None else ChainKey.from_file(key_file)
        """The server's key (``--key``): recovering a killed session's shard signs with it."""
        self.folder = shard_folder(store)
        self._merging = threading.Lock()

    def new_shard(self) -> Path:
        """A path no session has used."""
        self.folder.mkdir(parents=True, exist_ok=True)
        return self.folder / f"{secrets.token_hex(8)}.sqlite"

    def merge(self, shard: Path) -> MergeReport | None:
        """Copy ``shard`` into the store and delete it (blocking); None when it holds no
        session (a session that failed to start). Raises StoreError when the merge fails;
        the shard is then kept."""
        with self._merging:
            if not shard.is_file():
                return None
            report = merge_stores([shard], self.store, verify="shards", key=self.key)
            remove_shard(shard)
            return report

    def leftovers(self) -> list[Path]:
        """Shards an earlier run did not merge, oldest first."""
        if not self.folder.is_dir():
            return []
        return sorted(self.folder.glob("*.sqlite"), key=lambda p: p.stat().st_mtime)

    def merge_leftovers(self) -> list[str]:
        """Merge every leftover shard; one line per shard saying what happened."""
        lines = []
        for shard in self.leftovers():
            try:
                report = self.merge(shard)
            except StoreError as error:
                lines.append(f"{shard}: not merged ({error}); it stays for the next start")
                continue
            if report is not None:
                recovered = report.recovered_trials
                lines.append(
                    f"{shard}: merged into {self.store}"
                    + (f" ({recovered} trial(s) a killed process left open recovered as "
                       "interrupted)" if recovered else "")
                )  # fmt: skip
        return lines


def remove_shard(shard: Path) -> None:
    """A merged shard's files: its media folder, then every file named after it (the
    database, its WAL, lock and disk-reserve files), the database last."""
    shutil.rmtree(media_dir_for(shard), ignore_errors=True)
    for path in shard.parent.glob(glob.escape(shard.name) + "?*"):
        path.unlink(missing_ok=True)
    shard.unlink(missing_ok=True)
