"""Throughput against threads and Dask workers, and the projected curve for a
larger cluster (scaling.py draws it).

Measured on this machine, one image of the full dragon at the default settings:
- rtcore's Scene.render on 1 and on 2 threads (no Dask);
- the job service's own tile task (server/app/services/tile_tasks.py) on a
  real Dask LocalCluster of 1 and of 2 single-threaded worker processes, the
  image cut as the service cuts it for that many threads (tile_plan.py), every
  task submitted at once and gathered.
The projection takes from these runs the render cost per pixel on one worker
thread (c), the overhead each task adds on its worker (o: the one-worker wall
time beyond the tiles' own and the job's latency), the serial cost of one task
at the scheduler and client (s = s0 + b * bytes: tasks that return a small and
a large tile's bytes without rendering) and a job's fixed latency (L: a
one-tile job). N workers then need, with the service's tiles for N threads
(`tiles` of `area` pixels each),
    T(N) = L + max(ceil(tiles / N) * (c * area + o), tiles * s(area))
for an image: the work splits over the workers until the tiles run out or the
scheduler's serial share dominates.
"""

from __future__ import annotations

import math
import os
import statistics
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


sys.path.insert(0, str(ROOT / "server"))
from app.services.tile_plan import TILE_SIZES  # noqa: E402

# Bytes a tile's result carries per pixel: float RGB layers and RGBA8 for the stream.
RESULT_BYTES_PER_PIXEL = 3 * 4 + 4


@dataclass
class Throughput:
    scene: str
    size: int
    threads: dict[int, float]    # rtcore threads: seconds per image
    workers: dict[int, float]    # Dask worker processes (1 thread each): seconds per image
    pixel_s: float               # c
    task_overhead_s: float       # o
    serial_s: float              # s0
    serial_s_per_byte: float     # b
    latency_s: float             # L
    pixel_rays: float            # the service's estimate of a pixel's rays (tile_plan.rays_per_pixel)

    def tiles(self, workers: int) -> tuple[int, int]:
        """(tile side, tiles) the service cuts the image into for `workers` threads."""
        from app.services.tile_plan import full_tile_size
        side = full_tile_size(self.size, self.size, workers, self.pixel_rays)
        return side, math.ceil(self.size / side) ** 2

    def projected(self, workers: int, side: int | None = None) -> float:
        """Seconds per image on `workers` workers of one thread, with the
        service's tiles or square tiles of `side` pixels."""
        side, tiles = self.tiles(workers) if side is None else (side, math.ceil(self.size / side) ** 2)
        area = side * side
        serial = self.serial_s + self.serial_s_per_byte * area * RESULT_BYTES_PER_PIXEL
        return self.latency_s + max(math.ceil(tiles / workers) * (self.pixel_s * area + self.task_overhead_s),
                                    tiles * serial)

    def best_side(self, workers: int) -> int:
        """The tile side of the service's sizes that the model says is fastest."""
        return min(TILE_SIZES, key=lambda side: self.projected(workers, side))


def _noop_tile(nbytes: int) -> bytes:
    return bytes(nbytes)


def median_time(run, repeats: int) -> float:
    """Median wall seconds of `repeats` calls of `run` after one to warm up."""
    run()  # warm-up: scene loads, worker imports
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def measure(scene_path: Path, size: int = 1024, repeats: int = 3) -> Throughput:
    # Workers are separate processes: they find the service's task module and rtcore the way
    # `dask worker` processes of the cluster topology do, through PYTHONPATH.
    import rtcore
    os.environ["PYTHONPATH"] = os.pathsep.join(
        [str(ROOT / "server"), str(Path(rtcore.__file__).parent)] + [p for p in sys.path if p])
    from distributed import Client, LocalCluster, wait
    from rt import job_pb2, render_pb2

    from app.services import layer_files
    from app.services.cluster import RenderWorkerSetup
    from app.services.data_access import FOLDER_ID_FILE, DataAccess
    from app.services.tile_plan import TileSpec, grid_size, plan_passes, rays_per_pixel
    from app.services.tile_tasks import render_tile

    scene = rtcore.Scene.load(str(scene_path))
    camera = scene.default_camera
    settings = render_pb2.RenderSettings(width=size, height=size)
    request = job_pb2.JobRequest(scene_id="bench", camera=render_pb2.Camera.FromString(camera),
                                 settings=settings).SerializeToString()
    threads = {n: median_time(lambda n=n: scene.render(camera, settings.SerializeToString(), n, 32), repeats)
               for n in (1, 2)}
    scene_key = f"scaling-{scene_path.name}"
    pixel_rays = rays_per_pixel(settings, job_pb2.SceneInfo.FromString(scene.info).lights)

    # The tasks write their layers, as the service's do.
    scratch = tempfile.TemporaryDirectory(prefix="rt-scaling-")
    layers = ""
    # A data folder the workers see (the service's shared-folder case): they
    # read the scene from its path and write their tiles into the layer files.
    data = Path(scratch.name)
    (data / "jobs").mkdir()
    (data / FOLDER_ID_FILE).write_text("bench")
    access = DataAccess(str(data), "bench", "http://unused", "unused")

    def run_image(client, tiles) -> list[job_pb2.TileResult]:
        futures = [client.submit(render_tile, access, scene_key, str(scene_path), request, "bench", "bench", layers, t,
                                 pure=False)
                   for t in tiles]
        wait(futures)
        return client.gather(futures)

    def serial_per_task(client, side: int, count: int) -> float:
        payload = side * side * RESULT_BYTES_PER_PIXEL
        return median_time(lambda: client.gather(
            [client.submit(_noop_tile, payload, pure=False) for _ in range(count)]), repeats) / count

    workers = {}
    for n in (1, 2):
        # The service's full-resolution pass for n threads, in its centre-out order.
        tiles = plan_passes(size, size, n, interactive=False, pixel_rays=pixel_rays)[-1]
        layers = str(layer_files.create(data / "jobs" / f"bench-{n}", size, size, grid_size(tiles), []))
        with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
                Client(cluster) as client:
            client.register_plugin(RenderWorkerSetup())  # as the service does: one render thread per Dask thread
            workers[n] = median_time(lambda: run_image(client, tiles), repeats)
            if n == 1:
                rendered = sum(r.seconds for r in run_image(client, tiles))
                pixel_s = rendered / (size * size)
                latency = median_time(lambda: run_image(client, [TileSpec(0, 0, 0, 1, 1, 1, 0)]), repeats)
                overhead = max(0.0, (workers[1] - rendered - latency) / len(tiles))
            else:
                small, large = serial_per_task(client, 32, 256), serial_per_task(client, 256, 32)
                per_byte = max(0.0, (large - small) / ((256 * 256 - 32 * 32) * RESULT_BYTES_PER_PIXEL))
    scratch.cleanup()
    return Throughput(scene=scene_path.name, size=size, threads=threads, workers=workers, pixel_s=pixel_s,
                      task_overhead_s=overhead, serial_s=max(0.0, small - per_byte * 32 * 32 * RESULT_BYTES_PER_PIXEL),
                      serial_s_per_byte=per_byte, latency_s=latency, pixel_rays=pixel_rays)


def pixels_per_second(t: Throughput, seconds: float) -> float:
    return t.size * t.size / seconds


def projection_table(t: Throughput, counts=(1, 2, 4, 8, 16, 32, 64, 128, 256)) -> list[tuple[int, float]]:
    return [(n, t.projected(n)) for n in counts]


def summary_rows(t: Throughput) -> list[list[str]]:
    mpix = lambda s: f"{pixels_per_second(t, s) / 1e6:.3g}"  # noqa: E731
    rows = [[f"rtcore, {n} thread{'s' * (n > 1)}", "measured", "-", f"{s * 1000:.0f}", mpix(s)]
            for n, s in t.threads.items()]
    rows += [[f"Dask, {n} worker{'s' * (n > 1)} x 1 thread", "measured", "{0}x{0}, {1}".format(*t.tiles(n)),
              f"{s * 1000:.0f}", mpix(s)] for n, s in t.workers.items()]
    rows += [[f"Dask, {n} workers", "projected", "{0}x{0}, {1}".format(*t.tiles(n)), f"{s * 1000:.0f}", mpix(s)]
             for n, s in projection_table(t) if n in (1, 2, 8, 32, 128)]
    for n in (32, 128):
        side = t.best_side(n)
        seconds = t.projected(n, side)
        rows.append([f"Dask, {n} workers", "projected, best tile size", f"{side}x{side}, "
                     f"{math.ceil(t.size / side) ** 2}", f"{seconds * 1000:.0f}", mpix(seconds)])
    return rows


def model_text(t: Throughput) -> str:
    return (f"c = {t.pixel_s * 1e6:.2f} us per pixel, o = {t.task_overhead_s * 1000:.2f} ms per task, "
            f"s = {t.serial_s * 1000:.2f} ms + {t.serial_s_per_byte * 1e9:.2f} ns per result byte per task at the "
            f"scheduler and client, L = {t.latency_s * 1000:.1f} ms per job")


def ideal(t: Throughput, workers: int) -> float:
    """Seconds per image if the one-worker time split perfectly."""
    return t.workers[1] / workers
