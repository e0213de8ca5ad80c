"""How a job's image is cut into Dask tasks: passes, tile sizes, order and priority.

A large image that someone waits for first gets a preview pass (one pixel per
8x8 block, cheap) so the viewer shows the whole picture at once; the
full-resolution pass then refines it. A preview pixel is final (the full
render computes it the same way), so each full-resolution tile takes its
preview's pixels instead of tracing them again. The preview is not free,
though: its pixels cost about twice a full tile's (its 4 x 4 camera packets
span 32 x 32 pixels), a tile's packets still trace 15 rays where one pixel is
known, and it is a task more. On a 1024 x 1024 dragon at one sample that was
3% of the render and 5% of the service's throughput, so only interactive jobs
and batch jobs long enough for someone to want to see them early
(PREVIEW_MIN_RAYS_PER_THREAD) get one. Tiles run centre-out, where the subject
usually is. Priorities make the cluster fair: an interactive job outranks batch
jobs, any job's preview outranks full-resolution tiles, and tiles of equal rank
from different jobs interleave instead of one job waiting for another to finish.

Tile size follows the work per pixel. A tile renders on all of its worker's
cores (rtcore's render pool), and a worker holds two tiles at a time, one
rendering and the next waiting (tile_slots.py); two tiles a thread in all
make each a small share of its worker's work, so that workers end together.
Beyond that, a task costs the server's event loop Dask's bookkeeping whatever
its size, so a cheap image gets large tiles (a 1024 x 1024 dragon at one
sample: 4 tiles of 512, instead of 16 of 256 that took 4% of the image's CPU
in bookkeeping), and an expensive one small tiles, so that a tile ends in a
fraction of a second: an interactive job waits at most that long for a
worker, and viewers see the image advance. A job that would need more than
MAX_TILES such tiles gets fewer, longer ones.

On a large cluster the count of tiles has a ceiling of its own. Dask's
scheduler handles tasks one at a time, 0.6 to 0.85 ms of its CPU each on this
machine with 1 to 16 workers of 8 threads (renderer/bench/dask_costs.py), and
the server 0.57 ms per result and 0.8 ns per byte of its message besides.
Two tiles a thread would cut a 3840 x 2160 dragon at 16 samples (32 rays a
pixel) on 32 such workers into 2040 tiles of 64: 1.5 s of scheduling for the
0.18 s each worker renders, 13% efficiency in the cluster model
(renderer/bench/cluster_model.py, docs/charts/scaling_cluster_model.md). So a
job gets no more tiles than the scheduler can hand out while the threads
render them: each must bring every thread TASK_RAYS_PER_THREAD rays. A thread
renders about 5.7M rays a second, 4K in the scheduler's turn for one task;
with 5K the scheduler is busy for at most four fifths of the render (8K, as
first chosen, left room for too few tiles: the job below got 135, 74%).

The limit falls between tile sizes, whose counts come in steps of four: the
job above could have 135 tiles of 256 or 510 of 128, too few or too many. With
135 the tiles' costs differ (the dragon's up to 5 times the background's) and
a worker holds its next tile while it renders one, so the workers that took
costly tiles late end late: 74%. So when the limit stops the grid short of the
next smaller tiles, as many of its middle tiles as the scheduler has room for
are cut in four, and the quarters run last: the tiles that cost most, where
the subject usually is, are smaller, and the last round is of small tiles, so
that the workers end together. The job gets 201 tiles (113 of 256, then 88 of
128): 90% (56% when Dask dealt its 135 tiles by count). With 16 to 48 tiles
cut that was 87-91%; the quarters run centre-out among the rest gave 80-91%,
and cutting the outer tiles instead 75-81%. At 64 workers the scheduler hands
out about 100 tasks in the 94 ms each worker renders, fewer than two a worker,
and the costliest tile of 256 alone takes 135 ms: 47-49%, cut or not. At one
sample the same image is 10 ms of rendering per thread at 32 workers: the
server's handling of its 33 MB of RGBA8 messages and a job's latency bound it
(16%). Small clusters keep their plans but for tiny images: on 2 threads the
limit binds only below 40K rays (a 160 x 120 image at one sample of one light
gets 2 tiles instead of 6, which its worker renders on both threads all the
same).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

from rt import job_pb2, render_pb2, scene_pb2

PREVIEW_SCALE = 8
PREVIEW_MIN_PIXELS = 256 * 256   # smaller images are fast enough without a preview
# A batch job gets a preview when its camera and shadow rays (rays_per_pixel)
# are more than this per thread of the cluster: several rounds of tiles, a
# second or more.
PREVIEW_MIN_RAYS_PER_THREAD = 8 * (1 << 20)
PREVIEW_TILE = 1024              # 128 x 128 samples a task: one for a 1024 x 1024 image
TILE_SIZES = (512, 256, 128, 64, 32, 16)
TILES_PER_THREAD = 2             # enough tiles: each a small share of its worker's work
TILE_RAYS = 1 << 20              # a tile's estimated rays: ~0.15 s on 2 cores
# Tasks of one job at most (unless its threads need more): Dask's bookkeeping
# grows with them, cancelling a graph as their square (4096 tiles sharing a
# preview took the event loop 1.7 s to cancel).
MAX_TILES = 1024
# Dask's scheduler handles tasks one at a time, so a task must bring the
# cluster enough work to pay for its turn: at least this many rays per thread
# of the cluster, what a thread renders in about 1.25 times the scheduler's
# time for one task (the module's docstring has the figures).
TASK_RAYS_PER_THREAD = 5 * 1024

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


def rays_per_pixel(settings: render_pb2.RenderSettings, lights: Iterable[scene_pb2.LightSpec]) -> float:
    """The rays a pixel is expected to cost before any reflection: per camera
    sample (of every frame averaged), the primary ray and the shadow rays, one
    per point, spot or hard directional light and light_samples per spherical
    light or directional light of some angular diameter. An upper bound
    where adaptive sampling stops early; reflections add to it."""
    samples = settings.samples_per_pixel
    if settings.motion_blur == render_pb2.FRAMES:
        samples *= settings.motion_frames
    return samples * (1 + sum(settings.light_samples if light.radius > 0 or light.angular_diameter > 0 else 1
                              for light in lights))


def schedulable_tiles(width: int, height: int, threads: int, pixel_rays: float = 1.0) -> float:
    """How many tasks Dask's scheduler can hand out, one after another, in
    about the time the cluster's threads take to render the image: each must
    bring every thread TASK_RAYS_PER_THREAD rays (unlimited when that is 0)."""
    if not TASK_RAYS_PER_THREAD:
        return math.inf
    return width * height * pixel_rays / (max(threads, 1) * TASK_RAYS_PER_THREAD)


def _tile_counts(width: int, height: int, threads: int, pixel_rays: float) -> tuple[float, float, bool]:
    """Enough tiles to keep every thread busy (or as many as the scheduler
    can hand out in time, if fewer), too many tasks (more than MAX_TILES,
    unless the threads need them, or than the scheduler can hand out in
    time), and whether the scheduler sets that limit."""
    threads = max(threads, 1)
    schedulable = max(1.0, schedulable_tiles(width, height, threads, pixel_rays))
    busy = TILES_PER_THREAD * threads
    return min(busy, schedulable), min(max(MAX_TILES, busy), schedulable), schedulable < max(MAX_TILES, busy)


def full_tile_size(width: int, height: int, threads: int, pixel_rays: float = 1.0) -> int:
    """The largest tile within the ray budget that still makes enough tiles;
    over budget when the next smaller tile would make too many; and short of
    enough when the scheduler's limit is what the next smaller tile would
    pass (full_tiles then cuts the middle tiles, as many as it has room for)."""
    enough, limit, scheduler_limited = _tile_counts(width, height, threads, pixel_rays)
    counts = [_blocks(width, size) * _blocks(height, size) for size in TILE_SIZES]
    for i, size in enumerate(TILE_SIZES):
        smallest = i + 1 == len(TILE_SIZES)
        finer_too_many = not smallest and counts[i + 1] > limit
        if counts[i] < enough and not (scheduler_limited and finer_too_many):
            continue
        if size * size * pixel_rays <= TILE_RAYS or smallest or finer_too_many:
            return size
    return TILE_SIZES[-1]


Rect = tuple[int, int, int, int]


def _centre_out(rects: list[Rect], width: int, height: int) -> list[Rect]:
    cx, cy = width / 2, height / 2
    return sorted(rects, key=lambda r: ((r[0] + r[2] / 2 - cx) ** 2 + (r[1] + r[3] / 2 - cy) ** 2, r[1], r[0]))


def _grid(width: int, height: int, size: int) -> list[Rect]:
    return _centre_out([(x, y, min(size, width - x), min(size, height - y))
                        for y in range(0, height, size) for x in range(0, width, size)], width, height)


def _quarters(rect: Rect, size: int) -> list[Rect]:
    """A tile of a grid of `size` (clipped at the image's edge) as the tiles of the grid of size / 2 it covers."""
    x, y, w, h = rect
    half = size // 2
    return [(qx, qy, min(half, x + w - qx), min(half, y + h - qy))
            for qy in range(y, y + h, half) for qx in range(x, x + w, half)]


def full_tiles(width: int, height: int, threads: int, pixel_rays: float = 1.0) -> list[Rect]:
    """The full-resolution tiles in the order they run: full_tile_size's
    grid centre-out; and when the scheduler's limit stopped it short of
    smaller tiles (its tiles over the ray budget, or fewer than enough), as
    many of its middle tiles as the scheduler has room for cut in four, which
    run last (the module's docstring says why)."""
    size = full_tile_size(width, height, threads, pixel_rays)
    rects = _grid(width, height, size)
    enough, limit, scheduler_limited = _tile_counts(width, height, threads, pixel_rays)
    short = len(rects) < enough or size * size * pixel_rays > TILE_RAYS
    if not scheduler_limited or not short or size == TILE_SIZES[-1]:
        return rects
    quarters: list[Rect] = []
    count, cut = len(rects), 0
    for rect in rects:  # centre-out: the middle ones first
        parts = _quarters(rect, size)  # fewer than four where the image's edge clips the tile
        if count + len(parts) - 1 > limit:
            break
        count, cut = count + len(parts) - 1, cut + 1
        quarters += parts
    return rects[cut:] + _centre_out(quarters, width, height)


def wants_preview(width: int, height: int, threads: int, interactive: bool, pixel_rays: float) -> bool:
    """Whether the image gets a preview pass: a large one that someone waits
    for, or a batch job's that takes long."""
    if width * height < PREVIEW_MIN_PIXELS:
        return False
    return interactive or width * height * pixel_rays > PREVIEW_MIN_RAYS_PER_THREAD * max(threads, 1)


def plan_passes(width: int, height: int, threads: int, interactive: bool,
                pixel_rays: float = 1.0) -> list[list[TileSpec]]:
    """The passes of a width x height image for a cluster of `threads` threads,
    whose pixels cost about `pixel_rays` rays each (rays_per_pixel)."""
    boost = INTERACTIVE_BOOST if interactive else 0
    passes: list[list[TileSpec]] = []
    previews: dict[tuple[int, int], TileSpec] = {}
    if wants_preview(width, height, threads, interactive, pixel_rays):
        passes.append([TileSpec(0, x, y, w, h, PREVIEW_SCALE, boost + PREVIEW_BOOST - i)
                       for i, (x, y, w, h) in enumerate(_grid(width, height, PREVIEW_TILE))])
        previews = {(p.x, p.y): p for p in passes[0]}
    index = len(passes)
    # Every tile size divides PREVIEW_TILE and is a multiple of PREVIEW_SCALE:
    # a tile lies in one preview tile and starts on its grid.
    passes.append([TileSpec(index, x, y, w, h, 1, boost - i,
                            previews.get((x - x % PREVIEW_TILE, y - y % PREVIEW_TILE)))
                   for i, (x, y, w, h) in enumerate(full_tiles(width, height, threads, pixel_rays))])
    return passes


def grid_size(tiles: list[TileSpec]) -> int:
    """The edge of the blocks a pass's tiles are stored in (layer_files): the
    grid every tile starts on, that of its largest tiles or, where middle
    tiles were cut in four, of the quarters (a tile then covers whole blocks
    of it, or ends at the image's edge); one tile's own edge."""
    starts = {t.x for t in tiles} | {t.y for t in tiles}
    starts.discard(0)
    return math.gcd(*starts) if starts else max(max(t.w, t.h) for t in tiles)
