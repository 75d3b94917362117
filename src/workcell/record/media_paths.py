"""Where a store's camera videos live: ``<store>.media/<trial_id>/<camera>.mp4``.

A trial's ``media`` event names each file relative to the folder of the store that recorded
it (``shard-0.sqlite.media/<trial_id>/head_cam.mp4`` for a worker's shard). A merged store
keeps its events as they were written (their rows are checksummed and chained), so a file
is looked for where the event says and then in the store's own media folder, under
``<trial_id>/<camera>.mp4``, where :func:`copy_media` puts the videos of merged shards.
Readers check each file's sha256 and frame count against the event, so finding a file in
either place proves nothing until that check passes.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path, PurePosixPath


def media_dir_for(store_path: Path) -> Path:
    return store_path.with_name(f"{store_path.name}.media")


def recorded_file_path(store_path: Path, file: str) -> Path:
    """The path of a file a ``media`` event of the store at ``store_path`` names."""
    as_recorded = store_path.parent / file
    if as_recorded.is_file():
        return as_recorded
    in_own_folder = media_dir_for(store_path).joinpath(*PurePosixPath(file).parts[-2:])
    return in_own_folder if in_own_folder.is_file() else as_recorded


def copy_media(source_store: Path, target_store: Path) -> int:
    """Put the trial folders of ``source_store``'s media folder into ``target_store``'s
    (hard links where the file system allows, copies elsewhere); the number of files added.
    A file already there is left alone (merging the same shard twice adds nothing)."""
    source = media_dir_for(source_store)
    if not source.is_dir():
        return 0
    target = media_dir_for(target_store)
    added = 0
    for trial in sorted(p for p in source.iterdir() if p.is_dir()):
        for file in sorted(p for p in trial.iterdir() if p.is_file()):
            destination = target / trial.name / file.name
            if destination.exists():
                continue
            destination.parent.mkdir(parents=True, exist_ok=True)
            try:
                os.link(file, destination)
            except OSError:
                shutil.copy2(file, destination)
            added += 1
    return added
