"""How much the data folder holds and how much its disk has left (/api/health)."""

from __future__ import annotations

import os
import shutil
from pathlib import Path


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
