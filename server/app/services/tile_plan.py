"""How a job's image is cut into Dask tasks: passes, tile sizes, order and priority.

A large image first gets a preview pass (one sample per 8x8 block, cheap) so the
viewer shows the whole picture at once; the full-resolution pass then refines
it. Tiles run centre-out, where the subject usually is. Priorities make the
cluster fair: an interactive job outranks batch jobs, any job's preview outranks
full-resolution tiles, and tiles of equal rank from different jobs interleave
instead of one job waiting for another to finish.
"""

from __future__ import annotations

from dataclasses import dataclass

from rt import job_pb2

PREVIEW_SCALE = 8
PREVIEW_MIN_PIXELS = 256 * 256   # smaller images are fast enough without a preview
PREVIEW_TILE = 1024              # 128 x 128 samples a task: one for a 1024 x 1024 image
TILE_SIZES = (256, 128, 64, 32, 16)
TILES_PER_THREAD = 4             # enough tasks to balance the load on every thread

INTERACTIVE_BOOST = 10_000_000
PREVIEW_BOOST = 1_000_000


@dataclass(frozen=True)
class TileSpec:
    pass_index: int
    x: int
    y: int
    w: int
    h: int
    scale: int
    priority: int

    def region(self) -> job_pb2.TileRegion:
        return job_pb2.TileRegion(**{"pass": self.pass_index}, x=self.x, y=self.y, w=self.w, h=self.h)

    @property
    def samples(self) -> int:
        return -(-self.w // self.scale) * -(-self.h // self.scale)


def full_tile_size(width: int, height: int, threads: int) -> int:
    """The largest tile that still gives every thread enough tiles."""
    for size in TILE_SIZES:
        if -(-width // size) * -(-height // size) >= TILES_PER_THREAD * max(threads, 1):
            return size
    return TILE_SIZES[-1]


def _grid(width: int, height: int, size: int) -> list[tuple[int, int, int, int]]:
    rects = [(x, y, min(size, width - x), min(size, height - y))
             for y in range(0, height, size) for x in range(0, width, size)]
    cx, cy = width / 2, height / 2
    return sorted(rects, key=lambda r: ((r[0] + r[2] / 2 - cx) ** 2 + (r[1] + r[3] / 2 - cy) ** 2, r[1], r[0]))


def plan_passes(width: int, height: int, threads: int, interactive: bool) -> list[list[TileSpec]]:
    boost = INTERACTIVE_BOOST if interactive else 0
    passes: list[list[TileSpec]] = []
    if width * height >= PREVIEW_MIN_PIXELS:
        passes.append([TileSpec(0, x, y, w, h, PREVIEW_SCALE, boost + PREVIEW_BOOST - i)
                       for i, (x, y, w, h) in enumerate(_grid(width, height, PREVIEW_TILE))])
    size = full_tile_size(width, height, threads)
    index = len(passes)
    passes.append([TileSpec(index, x, y, w, h, 1, boost - i)
                   for i, (x, y, w, h) in enumerate(_grid(width, height, size))])
    return passes
