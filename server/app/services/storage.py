"""How much the data folder holds and how much its disk has left (/api/health),
and what a write into a full one raises."""

from __future__ import annotations

import errno
import math
import os
import shutil
import sqlite3
import threading
import time
from pathlib import Path

# A full disk, or the user's or the filesystem's quota reached.
FULL_ERRNOS = (errno.ENOSPC, errno.EDQUOT)


def folder_bytes(folder: Path) -> int:
    """The bytes of every file under `folder` (links not followed); 0 when it is missing."""
    total = 0
    stack = [folder]
    while stack:
        try:
            entries = os.scandir(stack.pop())
        except OSError:  # gone meanwhile (a job deleted), or never made
            continue
        with entries:
            for entry in entries:
                try:
                    if entry.is_dir(follow_symlinks=False):
                        stack.append(Path(entry.path))
                    elif entry.is_file(follow_symlinks=False):
                        total += entry.stat(follow_symlinks=False).st_blocks * 512
                except OSError:
                    continue
    return total


# Walking the data folder takes time that grows with its files (tens of ms
# with a few thousand jobs), and monitors ask /api/health often: its size is
# walked again at most this often, or at once after a deletion (forget_size),
# where users look for the room they made; free space, which costs one
# statvfs, is always fresh.
SIZE_MAX_AGE_SECONDS = 10.0
_sizes: dict[Path, tuple[float, int]] = {}
_walking = threading.Lock()


def forget_size(data_dir: Path) -> None:
    _sizes.pop(data_dir, None)


def fresh_usage(data_dir: Path) -> tuple[int, int] | None:
    """usage() when the folder's size needs no walk (no thread needed), else None."""
    walked, size = _sizes.get(data_dir, (-math.inf, 0))
    if time.monotonic() - walked > SIZE_MAX_AGE_SECONDS:
        return None
    return size, shutil.disk_usage(data_dir).free


def usage(data_dir: Path) -> tuple[int, int]:
    """(bytes the data folder takes on disk, as walked in the last
    SIZE_MAX_AGE_SECONDS; bytes free on its disk). One caller walks at a time;
    the others meanwhile take the last size."""
    walked, size = _sizes.get(data_dir, (-math.inf, 0))
    if time.monotonic() - walked > SIZE_MAX_AGE_SECONDS and _walking.acquire(blocking=data_dir not in _sizes):
        try:
            size = folder_bytes(data_dir)
            _sizes[data_dir] = (time.monotonic(), size)
        finally:
            _walking.release()
    return size, shutil.disk_usage(data_dir).free


def is_full(error: BaseException) -> bool:
    """Whether `error` says the data folder's disk (or its quota) is full: an
    OSError's errno, or SQLite's own words for it."""
    if isinstance(error, OSError):
        return error.errno in FULL_ERRNOS
    return isinstance(error, sqlite3.OperationalError) and "disk is full" in str(error)


def full_message(data_dir: Path, error: BaseException) -> str:
    """What a user is told when a write into the data folder found no room."""
    try:
        free = f"{shutil.disk_usage(data_dir).free} bytes free"
    except OSError:
        free = "its free space unknown"
    return (f"the server's data folder is full ({free}): {error.strerror if isinstance(error, OSError) else error}; "
            "delete jobs or scenes, or ask its operator for room")
