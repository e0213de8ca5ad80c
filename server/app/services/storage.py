"""How much the data folder holds and how much its disk has left (/api/health),
and what a write into a full one raises."""

from __future__ import annotations

import errno
import os
import shutil
import sqlite3
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


def usage(data_dir: Path) -> tuple[int, int]:
    """(bytes the data folder takes on disk, bytes free on its disk)."""
    return folder_bytes(data_dir), shutil.disk_usage(data_dir).free


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
