"""How a job's image is cut into Dask tasks: passes, tile sizes, order and priority.

A large image first gets a preview pass (one pixel per 8x8 block, cheap) so the
viewer shows the whole picture at once; the full-resolution pass then refines
it. A preview pixel is final (the full render computes it the same way), so
each full-resolution tile takes its preview's pixels instead of tracing them
again: the preview costs nothing. Tiles run centre-out, where the subject
usually is. Priorities make the cluster fair: an interactive job outranks batch
jobs, any job's preview outranks full-resolution tiles, and tiles of equal rank
from different jobs interleave instead of one job waiting for another to finish.
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
    preview: TileSpec | None = None  # the preview tile that computed this tile's pixels on its grid

    def region(self) -> job_pb2.TileRegion:
        return job_pb2.TileRegion(**{"pass": self.pass_index}, x=self.x, y=self.y, w=self.w, h=self.h)

    def preview_window(self) -> tuple[slice, slice]:
        """Rows and columns of the preview's layers that hold this tile's pixels on its grid."""
        s = self.preview.scale
        j, i = (self.y - self.preview.y) // s, (self.x - self.preview.x) // s
        return slice(j, j + _blocks(self.h, s)), slice(i, i + _blocks(self.w, s))

    @property
    def pixels(self) -> int:
        """The pixels this tile traces: one per scale x scale block, less those its preview traced."""
        traced = _blocks(self.w, self.scale) * _blocks(self.h, self.scale)
        if self.preview is not None:
            traced -= _blocks(self.w, self.preview.scale) * _blocks(self.h, self.preview.scale)
        return traced


def _blocks(extent: int, scale: int) -> int:
    return -(-extent // scale)


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
    previews: dict[tuple[int, int], TileSpec] = {}
    if width * height >= PREVIEW_MIN_PIXELS:
        passes.append([TileSpec(0, x, y, w, h, PREVIEW_SCALE, boost + PREVIEW_BOOST - i)
                       for i, (x, y, w, h) in enumerate(_grid(width, height, PREVIEW_TILE))])
        previews = {(p.x, p.y): p for p in passes[0]}
    size = full_tile_size(width, height, threads)
    index = len(passes)
    # Every tile size divides PREVIEW_TILE and is a multiple of PREVIEW_SCALE:
    # a tile lies in one preview tile and starts on its grid.
    passes.append([TileSpec(index, x, y, w, h, 1, boost - i,
                            previews.get((x - x % PREVIEW_TILE, y - y % PREVIEW_TILE)))
                   for i, (x, y, w, h) in enumerate(_grid(width, height, size))])
    return passes


def grid_size(tiles: list[TileSpec]) -> int:
    """The edge of the grid a pass's tiles start on: its largest tile's."""
    return max(max(t.w, t.h) for t in tiles)
