"""A job's linear layers on disk: one .npy file per layer (colour, then each
auxiliary output asked for), float32, in the job's folder, stored tile by
tile: (tile rows, tile columns, tile, tile, channels), so that a tile is one
contiguous write (row by row, its 3 KB writes cost 16-21 ms of CPU per
1024x1024 image; as whole blocks, 3-4 ms). layout.json gives the image size;
load() answers a layer as an image.

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

import json
import os
import shutil
from pathlib import Path

import numpy as np

PARTIAL = "part.layers"
COMPLETE = "layers"
LAYOUT = "layout.json"

# Channels of each auxiliary layer, as rtcore.render_tile returns them.
AUX_CHANNELS = {"depth": 1, "normal": 3, "albedo": 3, "bvh_cost": 2}


def create(job_folder: Path, width: int, height: int, tile: int, aux: list[str]) -> Path:
    """Empty (sparse) layer files for a job about to render, for tiles on a
    grid of `tile` pixels; their folder."""
    folder = job_folder / PARTIAL
    for stale in (folder, job_folder / COMPLETE):  # of a run the server restarted
        shutil.rmtree(stale, ignore_errors=True)
    folder.mkdir(parents=True)
    (folder / LAYOUT).write_text(json.dumps({"width": width, "height": height}))
    for name, channels in {"color": 3, **{a: AUX_CHANNELS[a] for a in aux}}.items():
        with open(folder / f"{name}.npy", "wb") as f:
            shape = (-(-height // tile), -(-width // tile), tile, tile, channels)
            header = {"descr": np.lib.format.dtype_to_descr(np.dtype(np.float32)), "fortran_order": False,
                      "shape": shape}
            np.lib.format.write_array_header_1_0(f, header)
            f.truncate(f.tell() + int(np.prod(shape)) * 4)  # zeros, written by no one
    return folder


def write_tile(folder: str | Path, x: int, y: int, layers: dict[str, np.ndarray]) -> None:
    """Writes a full-resolution tile's layers at (x, y), each as one block."""
    for name, values in layers.items():
        with open(Path(folder) / f"{name}.npy", "r+b") as f:
            np.lib.format.read_magic(f)
            (_, columns, tile, _, channels), _, _ = np.lib.format.read_array_header_1_0(f)
            h, w = values.shape[:2]
            if (h, w) == (tile, tile):
                block = np.ascontiguousarray(values, np.float32)  # a float32 layer as it is, not copied
            else:  # an edge tile fills the top left of its block
                block = np.zeros((tile, tile, channels), np.float32)
                block[:h, :w] = values.reshape(h, w, channels)
            os.pwrite(f.fileno(), block, f.tell() + ((y // tile) * columns + x // tile) * block.nbytes)


def complete(job_folder: Path) -> None:
    (job_folder / PARTIAL).replace(job_folder / COMPLETE)


# Where jobs finished before the layer files kept their layers, all in one zip.
LEGACY_FILE = "layers.npz"


def _legacy(job_folder: Path) -> Path | None:
    """The layers.npz of a job finished before the layer files, if that is what it has."""
    legacy = job_folder / LEGACY_FILE
    return legacy if not (job_folder / COMPLETE).is_dir() and legacy.is_file() else None


def names(job_folder: Path) -> list[str]:
    """The layers of a done job: "color" and its auxiliary outputs."""
    if legacy := _legacy(job_folder):
        with np.load(legacy) as saved:
            return sorted(saved.files)
    return sorted(p.stem for p in (job_folder / COMPLETE).glob("*.npy"))


def load(job_folder: Path, name: str, folder: str = COMPLETE) -> np.ndarray:
    """One layer as an image, (height, width, channels)."""
    if folder == COMPLETE and (legacy := _legacy(job_folder)):
        with np.load(legacy) as saved:
            return saved[name]
    size = json.loads((job_folder / folder / LAYOUT).read_text())
    blocks = np.load(job_folder / folder / f"{name}.npy", mmap_mode="r")
    rows, columns, tile, _, channels = blocks.shape
    image = blocks.transpose(0, 2, 1, 3, 4).reshape(rows * tile, columns * tile, channels)
    return image[:size["height"], :size["width"]]


def replace(job_folder: Path, name: str, image: np.ndarray, folder: str = PARTIAL) -> None:
    """Writes a whole layer (bloom's result) over the one in the files."""
    blocks = np.load(job_folder / folder / f"{name}.npy", mmap_mode="r+")
    rows, columns, tile, _, channels = blocks.shape
    padded = np.zeros((rows * tile, columns * tile, channels), np.float32)
    padded[:image.shape[0], :image.shape[1]] = image.reshape(image.shape[0], image.shape[1], channels)
    blocks[...] = padded.reshape(rows, tile, columns, tile, channels).transpose(0, 2, 1, 3, 4)
    blocks.flush()
