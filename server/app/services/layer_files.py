"""A job's linear layers on disk: one .npy file per layer (colour, then each
auxiliary output asked for), full image size, float32, in the job's folder.

Workers write their tiles straight into these files: a tile's floats go from
the renderer's buffer to the file in one copy, and neither Dask nor the
server's event loop carries them (assembling them there and saving the
image at the end took 4% of a job's CPU, and 12 MB per image through Dask for
a remote worker). Any worker that sees the shared data folder can write any
tile; a tile written twice (a worker killed mid-tile, its tile run again)
writes the same values, as a pixel depends only on its coordinates.

The server makes the files when the job starts, in a folder whose name says
they are incomplete, and renames it once every tile is in: `layers/` always
holds a whole image, which a restart can rely on.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np

PARTIAL = "part.layers"
COMPLETE = "layers"

# Channels of each auxiliary layer, as rtcore.render_tile returns them.
AUX_CHANNELS = {"depth": 1, "normal": 3, "albedo": 3, "bvh_cost": 2}


def create(job_folder: Path, width: int, height: int, aux: list[str]) -> Path:
    """Empty (sparse) layer files for a job about to render; their folder."""
    folder = job_folder / PARTIAL
    for stale in (folder, job_folder / COMPLETE):  # of a run the server restarted
        shutil.rmtree(stale, ignore_errors=True)
    folder.mkdir(parents=True)
    for name, channels in {"color": 3, **{a: AUX_CHANNELS[a] for a in aux}}.items():
        with open(folder / f"{name}.npy", "wb") as f:
            header = {"descr": np.lib.format.dtype_to_descr(np.dtype(np.float32)), "fortran_order": False,
                      "shape": (height, width, channels)}
            np.lib.format.write_array_header_1_0(f, header)
            f.truncate(f.tell() + height * width * channels * 4)  # zeros, written by no one
    return folder


def write_tile(folder: str | Path, x: int, y: int, layers: dict[str, np.ndarray]) -> None:
    """Writes a full-resolution tile's layers at (x, y) into the files of `folder`,
    row by row: positioned writes cost a third less than the page faults of
    writing through a memory map."""
    for name, values in layers.items():
        with open(Path(folder) / f"{name}.npy", "r+b") as f:
            np.lib.format.read_magic(f)
            (height, width, channels), _, _ = np.lib.format.read_array_header_1_0(f)
            start = f.tell()
            h, w = values.shape[:2]
            rows = np.ascontiguousarray(values.reshape(h, w, channels), dtype=np.float32)
            row_bytes = width * channels * 4
            for j in range(h):
                os.pwrite(f.fileno(), rows[j], start + (y + j) * row_bytes + x * channels * 4)


def complete(job_folder: Path) -> None:
    (job_folder / PARTIAL).replace(job_folder / COMPLETE)


# Where jobs finished before the layer files kept their layers, all in one zip.
LEGACY_FILE = "layers.npz"


def names(job_folder: Path) -> list[str]:
    """The layers of a done job: "color" and its auxiliary outputs."""
    if not (job_folder / COMPLETE).is_dir() and (job_folder / LEGACY_FILE).is_file():
        with np.load(job_folder / LEGACY_FILE) as saved:
            return sorted(saved.files)
    return sorted(p.stem for p in (job_folder / COMPLETE).glob("*.npy"))


def load(job_folder: Path, name: str, folder: str = COMPLETE, writable: bool = False) -> np.ndarray:
    """One layer, (height, width, channels), memory-mapped."""
    if folder == COMPLETE and not (job_folder / COMPLETE).is_dir() and (job_folder / LEGACY_FILE).is_file():
        with np.load(job_folder / LEGACY_FILE) as saved:
            return saved[name]
    return np.load(job_folder / folder / f"{name}.npy", mmap_mode="r+" if writable else "r")
