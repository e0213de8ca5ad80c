"""A job's linear layers on disk: one .npy file per layer (colour, then each
auxiliary output asked for), float32, in the job's folder, stored tile by
tile: (tile rows, tile columns, tile, tile, channels), so that a tile is one
contiguous write (row by row, its 3 KB writes cost 16-21 ms of CPU per
1024x1024 image; as whole blocks, 3-4 ms). layout.json gives the image size;
load() answers a layer as an image.

Workers write their tiles straight into these files: a tile's floats are
copied once, into a page-aligned block (edge tiles padded), and neither Dask
nor the server's event loop carries them (assembling them there and saving the
image at the end took 4% of a job's CPU, and 12 MB per image through Dask for
a remote worker). Any worker that sees the shared data folder can write any
tile; a tile written twice (a worker killed mid-tile, its tile run again)
writes the same values, as a pixel depends only on its coordinates.

Tiles go to disk with O_DIRECT where the filesystem takes it, past the page
cache: written through the cache, a 1024x1024 image's 12 MB were copied into
freshly allocated cache pages, 8-15 ms of a worker's CPU per image (half of
its tile tasks' own time), to be read back once at most, when the job's image
files are made. It also means a job is done only once its pixels are on the
disk. For that, a layer file's header is padded to DIRECT_ALIGN bytes, so that
every block of a tile of 32 pixels or more starts and ends on the alignment;
smaller tiles go through the cache.

The server makes the files when the job starts, in a folder whose name says
they are incomplete, and renames it once every tile is in: `layers/` always
holds a whole image, which a restart can rely on.
"""

from __future__ import annotations

import errno
import json
import mmap
import os
import re
import shutil
import threading
from pathlib import Path

import numpy as np
import rtcore
from rt import job_pb2

PARTIAL = "part.layers"
COMPLETE = "layers"
LAYOUT = "layout.json"

# Channels of each auxiliary layer, as rtcore.render_tile returns them.
AUX_CHANNELS = {name.lower(): rtcore.aux_channel_count(name)
                for name in job_pb2.AuxOutput.keys() if job_pb2.AuxOutput.Value(name) != 0}
# The colour before denoising, which the last pass writes (job_image.finish_layers).
NOISY = "noisy"


def create(job_folder: Path, width: int, height: int, tile: int, aux: list[str], noisy: bool = False) -> Path:
    """Empty (sparse) layer files for a job about to render, for tiles on a
    grid of `tile` pixels, and for the colour before denoising when `noisy`;
    their folder."""
    folder = job_folder / PARTIAL
    for stale in (folder, job_folder / COMPLETE):  # of a run the server restarted
        shutil.rmtree(stale, ignore_errors=True)
    folder.mkdir(parents=True)
    (folder / LAYOUT).write_text(json.dumps({"width": width, "height": height}))
    layers = {"color": 3, **{a: AUX_CHANNELS[a] for a in aux}, **({NOISY: 3} if noisy else {})}
    for name, channels in layers.items():
        with open(folder / f"{name}.npy", "wb") as f:
            shape = (-(-height // tile), -(-width // tile), tile, tile, channels)
            f.write(_aligned_header(shape))
            f.truncate(f.tell() + int(np.prod(shape)) * 4)  # zeros, written by no one
    return folder


# O_DIRECT's alignment of file offsets, sizes and memory: the largest logical
# block size of common disks, and the page size.
DIRECT_ALIGN = 4096


def _aligned_header(shape: tuple[int, ...]) -> bytes:
    """A .npy (1.0) header for float32 blocks of `shape`, padded with spaces to
    DIRECT_ALIGN bytes as the format allows (numpy pads to 64)."""
    text = repr({"descr": "<f4", "fortran_order": False, "shape": shape}).encode("latin1")
    length = DIRECT_ALIGN - len(np.lib.format.magic(1, 0)) - 2
    return np.lib.format.magic(1, 0) + length.to_bytes(2, "little") + text.ljust(length - 1) + b"\n"


# What _aligned_header (and numpy, for files of earlier versions) writes.
_HEADER_SHAPE = re.compile(rb"\{'descr': '<f4', 'fortran_order': False, 'shape': \(([0-9, ]*)\),? *\}")


def _read_header(f) -> tuple[tuple[int, ...], int]:
    """A layer file's shape of blocks, and where its floats start.

    numpy's own reader evaluates the header with ast.literal_eval, and
    CPython 3.11's AST constructor keeps its recursion depth per interpreter,
    not per thread: two render threads writing tiles at once failed a tile with
    "SystemError: AST constructor recursion depth mismatch" (gh-106905), about
    one job in a few thousand under load. These headers are ours, so a pattern
    reads them."""
    magic = f.read(10)
    match = _HEADER_SHAPE.fullmatch(f.read(int.from_bytes(magic[8:10], "little")).rstrip(b" \n")) \
        if magic[:8] == np.lib.format.magic(1, 0) else None
    if match is None:
        raise ValueError(f"{f.name}: not a layer file")
    return tuple(int(n) for n in match.group(1).split(b",") if n.strip()), f.tell()


def _blocks(path: Path, mode: str) -> np.memmap:
    """A layer file's blocks, mapped (mode "r" or "r+")."""
    with open(path, "rb") as f:
        shape, start = _read_header(f)
    return np.memmap(path, np.float32, mode, offset=start, shape=shape)


_staging = threading.local()


def _staging_block(shape: tuple[int, int, int]) -> np.ndarray:
    """A float32 array of `shape` in page-aligned memory (as O_DIRECT needs),
    this thread's own, reused from tile to tile: warm pages, not fresh ones."""
    count = shape[0] * shape[1] * shape[2]
    buffer = getattr(_staging, "buffer", None)
    if buffer is None or len(buffer) < count * 4:
        buffer = _staging.buffer = mmap.mmap(-1, count * 4)
    return np.frombuffer(buffer, np.float32, count).reshape(shape)


def _write_direct(path: Path, block: np.ndarray, offset: int) -> bool:
    """Writes a block with O_DIRECT; False when the filesystem refuses it."""
    try:
        fd = os.open(path, os.O_WRONLY | os.O_DIRECT)
    except OSError as e:
        if e.errno == errno.EINVAL:  # no O_DIRECT here (tmpfs before Linux 6.6, some FUSE)
            return False
        raise
    data = memoryview(block).cast("B")
    done = 0
    try:
        while done < len(data):
            done += os.pwrite(fd, data[done:], offset + done)
    except OSError as e:
        if e.errno == errno.EINVAL and done == 0:  # a stricter alignment than DIRECT_ALIGN
            return False
        raise
    finally:
        os.close(fd)
    return True


def write_tile(folder: str | Path, x: int, y: int, layers: dict[str, np.ndarray]) -> None:
    """Writes a full-resolution tile's layers at (x, y), each as the blocks it
    covers: one, or where the plan cut some tiles smaller (tile_plan.full_tiles)
    each of a larger tile's."""
    for name, values in layers.items():
        path = Path(folder) / f"{name}.npy"
        with open(path, "rb") as f:
            (_, columns, tile, _, channels), start = _read_header(f)
        height, width = values.shape[:2]
        values = values.reshape(height, width, channels)
        for by in range(0, height, tile):
            for bx in range(0, width, tile):
                offset = start + (((y + by) // tile) * columns + (x + bx) // tile) * tile * tile * channels * 4
                _write_block(path, values[by:by + tile, bx:bx + tile], offset, tile)


def _write_block(path: Path, values: np.ndarray, offset: int, tile: int) -> None:
    block = _staging_block((tile, tile, values.shape[2]))
    h, w = values.shape[:2]
    block[:h, :w] = values
    block[h:] = 0  # an edge tile fills the top left of its block
    block[:h, w:] = 0
    aligned = offset % DIRECT_ALIGN == 0 and block.nbytes % DIRECT_ALIGN == 0
    if not (aligned and _write_direct(path, block, offset)):
        with open(path, "r+b") as f:
            os.pwrite(f.fileno(), block, offset)


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
    blocks = _blocks(job_folder / folder / f"{name}.npy", "r")
    rows, columns, tile, _, channels = blocks.shape
    image = blocks.transpose(0, 2, 1, 3, 4).reshape(rows * tile, columns * tile, channels)
    if not image.flags.writeable:
        # One column of blocks (a job of one tile, say) reshapes without a
        # copy, into a view of the read-only file, which bindings that want a
        # plain array (FLIP's) refuse.
        image = image.copy()
    return image[:size["height"], :size["width"]]


def replace(job_folder: Path, name: str, image: np.ndarray, folder: str = PARTIAL) -> None:
    """Writes a whole layer (the last pass's results) over the one in the files."""
    blocks = _blocks(job_folder / folder / f"{name}.npy", "r+")
    rows, columns, tile, _, channels = blocks.shape
    padded = np.zeros((rows * tile, columns * tile, channels), np.float32)
    padded[:image.shape[0], :image.shape[1]] = image.reshape(image.shape[0], image.shape[1], channels)
    blocks[...] = padded.reshape(rows, tile, columns, tile, channels).transpose(0, 2, 1, 3, 4)
    blocks.flush()


def layer_message(name: str, array: np.ndarray, channels: list[str] = ()) -> job_pb2.Layer:
    """An array as an rt.Layer: a tile's (worker to server), or a whole image's with its channels' names."""
    return job_pb2.Layer(name=name, shape=array.shape, dtype=array.dtype.str, data=array.tobytes(), channels=channels)


def layer_array(layer: job_pb2.Layer) -> np.ndarray:
    return np.frombuffer(layer.data, np.dtype(layer.dtype)).reshape(tuple(layer.shape))
