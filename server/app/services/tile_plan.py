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
cores (rtcore's render pool), so a tile per thread in flight and one queued
keep a worker busy; beyond that, a task costs the server's event loop about 3
ms of Dask bookkeeping whatever its size, so a cheap image gets large tiles
(a 1024 x 1024 dragon at one sample: 4 tiles of 512, instead of 16 of 256 that
took 4% of the image's CPU in bookkeeping), and an expensive one small tiles,
so that a tile ends in a fraction of a second: an interactive job waits at
most that long for a thread, and viewers see the image advance. A job that
would need more than MAX_TILES such tiles gets fewer, longer ones.

On a large cluster the count of tiles has a ceiling of its own. Dask's
scheduler handles tasks one at a time, 1.0 to 1.2 ms of its CPU each on this
machine with 1 to 16 workers of 8 threads (medians, no trend with the
workers; renderer/bench/dask_costs.py), and the server 0.87 ms per result and
1.5 ns per byte of its message besides. Two tiles a thread cut a 3840 x 2160
dragon at 16 samples (32 rays a pixel) on 32 such workers into 2040 tiles of
64: 2.1 s of scheduling for the 0.24 s each thread renders, 12% efficiency in
the cluster model (renderer/bench/cluster_model.py,
docs/charts/scaling_cluster_model.md). So a job gets no more tiles than the
scheduler can hand out while the threads render them: each must bring every
thread TASK_RAYS_PER_THREAD rays, over the ray budget if need be. A thread
renders about 4.5M rays a second (447 ns a pixel of 2 rays), some 5K in the
scheduler's turn for one task; with 8K, and tile counts that come in steps of
four, the scheduler is busy for no longer than about the render. 16K (tried
first) gave the same at 32 workers but too few tiles at 16 (135 instead of
510: 79% against 90%) and at 64 (40 instead of 135: 20% against 43%). The job
above gets 135 tiles of 256 (59 ms each on a worker of 8 threads, on
average) and 59% in the model. What is left is the last round: Dask starts as
many tiles on a worker as it has threads, all at once, and never steals a
running one, so tiles are dealt by count, not cost (workers taking a tile at a
time would give 91%). At one sample the same image is 14 ms of rendering per
thread at 32 workers: the server's handling of its 33 MB of RGBA8 messages
and a job's latency bound it whatever the plan (1% before, 15% now). Small
clusters keep their plans: on 2 threads the limit can bind only below 64K
rays (a 90 x 90 image at one sample of one light: one tile instead of 4 of
64), and one worker of 8 threads gets what it got before.
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
TILES_PER_THREAD = 2             # one rendering and one queued on every thread
TILE_RAYS = 1 << 20              # a tile's estimated rays: ~0.15 s on 2 cores
# Tasks of one job at most (unless its threads need more): Dask's bookkeeping
# grows with them, cancelling a graph as their square (4096 tiles sharing a
# preview took the event loop 1.7 s to cancel).
MAX_TILES = 1024
# Dask's scheduler handles tasks one at a time, so a task must bring the
# cluster enough work to pay for its turn: at least this many rays per thread
# of the cluster, what a thread renders in about twice the scheduler's time for
# one task (the module's docstring has the figures).
TASK_RAYS_PER_THREAD = 8 * 1024

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


def full_tile_size(width: int, height: int, threads: int, pixel_rays: float = 1.0) -> int:
    """The largest tile within the ray budget that still gives every thread
    enough tiles, or the scheduler as many as it can hand out in time if
    that is fewer; over budget when the next smaller tile would make more than
    MAX_TILES tasks (and enough tiles do not need them) or more than the
    scheduler can hand out in time."""
    schedulable = max(1.0, schedulable_tiles(width, height, threads, pixel_rays))
    enough = min(TILES_PER_THREAD * max(threads, 1), schedulable)
    limit = min(max(MAX_TILES, TILES_PER_THREAD * max(threads, 1)), schedulable)
    counts = [_blocks(width, size) * _blocks(height, size) for size in TILE_SIZES]
    for i, size in enumerate(TILE_SIZES):
        if counts[i] < enough:
            continue
        smallest = i + 1 == len(TILE_SIZES)
        if size * size * pixel_rays <= TILE_RAYS or smallest or counts[i + 1] > limit:
            return size
    return TILE_SIZES[-1]


def _grid(width: int, height: int, size: int) -> list[tuple[int, int, int, int]]:
    rects = [(x, y, min(size, width - x), min(size, height - y))
             for y in range(0, height, size) for x in range(0, width, size)]
    cx, cy = width / 2, height / 2
    return sorted(rects, key=lambda r: ((r[0] + r[2] / 2 - cx) ** 2 + (r[1] + r[3] / 2 - cy) ** 2, r[1], r[0]))


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
    size = full_tile_size(width, height, threads, pixel_rays)
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
