"""A job's time on a cluster of W workers of 8 threads, modelled from measured
costs (dask_costs.py, tile_costs.py) and the tile plan the service really
makes for that image and cluster (tile_plan.plan_passes).

    T(W) = L + max(makespan, tasks * s(W), tasks * (r + r_b * bytes))

- makespan: the tiles dealt to the workers as the scheduler deals them
  (deal: each worker holds up to two tile tasks, tile_slots.py, the next in
  priority order going to the first worker with a free slot; a full tile is
  queued once its preview ends), each worker rendering the tiles it holds one
  after the other on all its threads (rtcore's render pool takes bands oldest
  tile first). A tile's work is its pixels' cost (the measured cost map, a
  preview pixel `preview_factor` times a full one) plus its constant cost on
  the worker (task, setup, sRGB encoding), in thread-seconds. This is the
  compute divided by the threads plus the imbalance of the last tiles.
  `dealing="dask"` models Dask's default instead, what the service had
  before: all of a job's tiles sent to the workers at once, in turn, when it
  has no more than twice as many as the cluster has threads, and otherwise
  1.1 a thread, 9 a worker of 8.
- tasks * s(W): the scheduler handles every task in one thread, at a
  measured CPU cost per task that may grow with the workers.
- tasks * (r + r_b * bytes): the server's event loop handles every result (the
  Dask client, the stream, the record), at a measured cost per result and per
  byte of its message.
- L: a one-task job's latency (graph sent, task run, result handled).

The three serial stages overlap (they are different processes), so the
slowest bounds the job. The dealing is what a real scheduler does
(dask_dealing.py, tasks that hold their worker's one lock, as tiles share its
render pool, sent as one graph): 32 tasks, every fourth 0.4 s and the rest
0.05 s, on 4 workers of 8 threads took 3.22 s dealt as Dask deals them by
default (modelled 3.20 s: one worker had all eight long ones) and 1.28 s
dealt as the service has them dealt (modelled 1.25 s; 11, 9, 7 and 5 tasks a
worker, as modelled); 96 tasks from 0.2 s down to 0.02 s on 8 workers took
1.12 s and 1.01 s (modelled 1.05 s and 0.96 s; 12 tasks a worker, and 9 to
14 where 10 to 13 were modelled; the rest is the job's latency and the
sleeps' overshoot on this busy machine). A worker holding its next tile
started it 0.16 ms (median) after the last; one holding a single tile waited
3.5 ms for the next (1.33 s and 1.05 s for the two jobs), which is why it
holds two.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "server"))
from app.services import tile_slots  # noqa: E402
from app.services.tile_plan import TileSpec, plan_passes  # noqa: E402

WORKER_COUNTS = (1, 2, 4, 8, 16, 32, 64)
DASK_WORKER_SATURATION = 1.1  # distributed's default


def dealing_slots(dealing: str, tasks: int, workers: int, threads: int) -> float:
    """Tasks a worker of `threads` threads holds at once, of a job of `tasks`
    on `workers` workers. The service has two at most (tile_slots.py). Dask
    by default queues a task group on the scheduler only when it has more
    than twice as many tasks as the cluster has threads, and then gives each
    worker 1.1 a thread (distributed.scheduler.worker-saturation); a smaller
    group goes to the workers all at once, in turn (Scheduler.is_rootish)."""
    if dealing == "dask":
        return math.inf if tasks <= 2 * threads * workers else math.ceil(DASK_WORKER_SATURATION * threads)
    return tile_slots.slots(threads, tile_slots.worker_saturation([threads]))


@dataclass(frozen=True)
class ClusterCosts:
    width: int
    height: int
    pixel_rays: float                 # tile_plan.rays_per_pixel for the job
    interactive: bool
    pixel_s: float                    # thread-seconds per pixel, the image's mean
    tile_s: float                     # thread-seconds per tile on its worker beyond its pixels
    encode_s_per_pixel: float         # thread-seconds to encode a tile's pixel to sRGB 8-bit
    preview_factor: float             # a preview pixel's cost over a full pixel's
    scheduler_s: dict[int, float]     # measured workers -> scheduler seconds per task
    server_s: float                   # the server's seconds per result
    server_s_per_byte: float          # and per byte of its message
    latency_s: float                  # a one-task job
    threads_per_worker: int = 8
    # How the scheduler deals tiles: "service", as the service has Dask deal
    # them (tile_slots.py); "dask", Dask's default (what the service did before).
    dealing: str = "service"
    slots_per_worker: int | None = None  # tasks a worker holds, instead of what the dealing gives
    # Relative cost of each cell x cell block of the image (mean 1); None: uniform.
    cost_map: np.ndarray | None = field(default=None, compare=False)
    cell: int = 64

    def scheduler_seconds(self, workers: int) -> float:
        """The scheduler's cost per task with `workers` workers: the measured
        figure, or beyond the measured range the least-squares line through the
        measured medians (never below the smallest)."""
        if workers in self.scheduler_s:
            return self.scheduler_s[workers]
        counts = sorted(self.scheduler_s)
        if len(counts) == 1:
            return self.scheduler_s[counts[0]]
        slope, intercept = np.polyfit(counts, [self.scheduler_s[n] for n in counts], 1)
        return max(float(intercept + slope * workers), min(self.scheduler_s.values()))

    def slots(self, tiles: int, workers: int) -> float:
        """Tile tasks a worker holds at once."""
        if self.slots_per_worker is not None:
            return self.slots_per_worker
        return dealing_slots(self.dealing, tiles, workers, self.threads_per_worker)

    def pixels_cost(self, x: int, y: int, w: int, h: int) -> float:
        """Thread-seconds to render every pixel of a rectangle."""
        if self.cost_map is None:
            return self.pixel_s * w * h
        c = self.cell
        rows, cols = self.cost_map.shape
        # Overlap of the rectangle with each cell row and column, in pixels.
        ys = np.clip(np.minimum(np.arange(1, rows + 1) * c, y + h) - np.maximum(np.arange(rows) * c, y), 0, None)
        xs = np.clip(np.minimum(np.arange(1, cols + 1) * c, x + w) - np.maximum(np.arange(cols) * c, x), 0, None)
        return self.pixel_s * float(ys @ self.cost_map @ xs)

    def tile_work(self, tile: TileSpec) -> float:
        """A tile's thread-seconds on its worker."""
        cost = self.pixels_cost(tile.x, tile.y, tile.w, tile.h)
        if tile.scale > 1:
            cost *= self.preview_factor / (tile.scale * tile.scale)
        # A full tile with a preview still traces whole packets (tile_plan.py): its full cost.
        traced = math.ceil(tile.w / tile.scale) * math.ceil(tile.h / tile.scale)
        return cost + self.tile_s + self.encode_s_per_pixel * traced

    def message_bytes(self, tile: TileSpec) -> int:
        return math.ceil(tile.w / tile.scale) * math.ceil(tile.h / tile.scale) * 4


@dataclass(frozen=True)
class Modelled:
    workers: int
    tiles: int
    tile_side: int                 # the full pass's largest tile edge
    makespan_s: float
    scheduler_s: float
    server_s: float
    latency_s: float

    @property
    def seconds(self) -> float:
        return self.latency_s + max(self.makespan_s, self.scheduler_s, self.server_s)

    @property
    def bound(self) -> str:
        """What limits the job: compute (with imbalance), scheduler or server."""
        parts = {"compute": self.makespan_s, "scheduler": self.scheduler_s, "server": self.server_s}
        return max(parts, key=parts.get)


def deal(works: list[float], workers: int, slots: float,
         after: list[int | None] | None = None) -> list[tuple[int, float, float]]:
    """Where and when each task runs (worker, start, end), tasks given in priority order with their seconds on
    a worker, dealt as Dask's scheduler deals queued tasks: whenever a worker
    has a free slot (it holds fewer than `slots`), the first task in priority
    order that can run goes to it (the least busy on a tie). A task that
    waits for another (`after`, an earlier index) is queued only once that one
    ends. A worker runs what it holds one after the other, on all its threads."""
    after = after or [None] * len(works)
    held: list[list[float]] = [[] for _ in range(workers)]  # end times of each worker's tasks, ascending
    ends: list[float | None] = [None] * len(works)
    dealt: list[tuple[int, float, float]] = [(0, 0.0, 0.0)] * len(works)
    pending = list(range(len(works)))
    now = 0.0

    def ready_at(i: int) -> float:  # when task i can be queued: inf while what it waits for is not dealt
        if after[i] is None:
            return 0.0
        end = ends[after[i]]
        return math.inf if end is None else end

    while pending:
        for h in held:
            h[:] = [end for end in h if end > now]
        # When each worker next has a free slot, and how many it holds then.
        free = [(now if len(h) < slots else h[len(h) - slots], min(len(h), slots - 1), w) for w, h in enumerate(held)]
        at, _, w = min(free)
        task = next((i for i in pending if ready_at(i) <= at), None)
        if task is None:  # every task left waits for one still running
            now = max(at, min(ready_at(i) for i in pending))
            continue
        now = at
        start = max(held[w][-1] if held[w] else 0.0, at)
        ends[task] = start + works[task]
        dealt[task] = (w, start, ends[task])
        held[w].append(ends[task])
        pending.remove(task)
    return dealt


def makespan(costs: ClusterCosts, tiles: list[TileSpec], workers: int) -> float:
    """When the last tile ends: tiles in priority order, dealt to the workers'
    slots (deal), a full tile queued once its preview ends."""
    order = sorted(tiles, key=lambda t: -t.priority)
    index = {t: i for i, t in enumerate(order)}
    after = [index.get(t.preview) if t.preview is not None else None for t in order]
    works = [costs.tile_work(t) / costs.threads_per_worker for t in order]
    return max((end for _, _, end in deal(works, workers, costs.slots(len(tiles), workers), after)), default=0.0)


def model(costs: ClusterCosts, workers: int, tiles: list[TileSpec] | None = None) -> Modelled:
    """The job on `workers` workers, with the service's plan for their threads
    unless `tiles` are given."""
    if tiles is None:
        passes = plan_passes(costs.width, costs.height, workers * costs.threads_per_worker, costs.interactive,
                             costs.pixel_rays)
        tiles = [t for p in passes for t in p]
    full = [t for t in tiles if t.scale == 1]
    n = len(tiles)
    message = sum(costs.message_bytes(t) for t in tiles)
    return Modelled(workers=workers, tiles=n, tile_side=max((max(t.w, t.h) for t in full), default=0),
                    makespan_s=makespan(costs, tiles, workers),
                    scheduler_s=n * costs.scheduler_seconds(workers),
                    server_s=n * costs.server_s + costs.server_s_per_byte * message,
                    latency_s=costs.latency_s)


@dataclass(frozen=True)
class Row:
    modelled: Modelled
    speedup: float
    efficiency: float


def scaling(costs: ClusterCosts, counts=WORKER_COUNTS, plan=None) -> list[Row]:
    """Speed-up and efficiency against one worker at each cluster size;
    `plan(workers)` gives the tiles (default: the service's plan)."""
    runs = [model(costs, n, plan(n) if plan else None) for n in counts]
    one = model(costs, 1, plan(1) if plan else None).seconds
    return [Row(m, one / m.seconds, one / (m.workers * m.seconds)) for m in runs]


def inputs_text(costs: ClusterCosts) -> str:
    """The model's measured inputs, in one line."""
    sched = ", ".join(f"{n}: {s * 1e6:.0f}" for n, s in sorted(costs.scheduler_s.items()))
    return (f"c = {costs.pixel_s * 1e9:.0f} ns per pixel on one thread ({costs.pixel_rays:g} rays a pixel), "
            f"preview pixel x{costs.preview_factor:.2f}, tile constant {costs.tile_s * 1e3:.2f} ms + "
            f"{costs.encode_s_per_pixel * 1e9:.1f} ns per pixel encoded; scheduler us per task by workers "
            f"{{{sched}}}; server {costs.server_s * 1e6:.0f} us per result + {costs.server_s_per_byte * 1e9:.2f} "
            f"ns per byte; latency {costs.latency_s * 1e3:.1f} ms; {costs.threads_per_worker} threads per worker")


def table_rows(rows: list[Row]) -> list[list[str]]:
    return [[r.modelled.workers, r.modelled.workers * 8, r.modelled.tiles, r.modelled.tile_side,
             f"{r.modelled.seconds * 1e3:.1f}", f"{r.speedup:.2f}", f"{100 * r.efficiency:.0f}%", r.modelled.bound]
            for r in rows]


TABLE_COLUMNS = ["workers", "threads", "tiles", "tile edge", "ms", "speed-up", "efficiency", "bound by"]
