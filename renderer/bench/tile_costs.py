"""What a tile costs its worker on this machine, on one thread (rtcore's render
pool set to one), in CPU seconds of this process (steadier than wall time on
cores shared with other work):

- the image's cost per pixel: Scene.render of the whole image at the job's
  settings (the defaults but for the samples per pixel), repeated;
- where that cost lies: each cell x cell block rendered as a tile, as a map of
  relative cost (mean 1) for the model's imbalance between tiles;
- a preview pixel's cost against a full one (the whole image at scale 8);
- a tile's constant: a 1 x 1 tile's render_tile (the renderer made from the
  settings and camera, the scene already loaded), and the sRGB encoding of a
  tile's pixels (rtcore.encode_srgb8, what a task does before answering).

`scale` > 1 measures an image that many times smaller and reads the map and
costs as if at full size (a quick test of the script, not a measurement).
"""

from __future__ import annotations

import math
import statistics
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dask_costs import Spread


@dataclass
class RenderCosts:
    scene: str
    width: int                    # the image the costs are for
    height: int
    measured_scale: int           # 1: measured at that size
    pixel_s: Spread               # thread-seconds per pixel, whole renders
    render_s: Spread              # thread-seconds per whole render
    cost_map: np.ndarray          # relative cost per cell (mean 1)
    cell: int
    preview_factor: float
    tile_s: Spread                # a 1 x 1 tile's render_tile
    encode_s_per_pixel: float
    pixel_rays: float


def _cpu(run) -> float:
    start = time.process_time()
    run()
    return time.process_time() - start


def measure(scene_path: Path, width: int = 3840, height: int = 2160, samples: int = 1, repeats: int = 3,
            cell: int = 64, scale: int = 1) -> RenderCosts:
    import rtcore
    from rt import job_pb2, render_pb2

    from app.services.tile_plan import PREVIEW_SCALE, rays_per_pixel

    rtcore.set_render_threads(1)
    scene = rtcore.Scene.load(str(scene_path))
    camera = scene.default_camera
    w, h, c = width // scale, height // scale, cell // scale
    settings = render_pb2.RenderSettings(width=w, height=h, samples_per_pixel=samples)
    encoded = settings.SerializeToString()
    pixel_rays = rays_per_pixel(settings, job_pb2.SceneInfo.FromString(scene.info).lights)

    scene.render_tile(camera, encoded, w // 2, h // 2, c, c)  # warm-up: caches, the pool's thread
    renders = [_cpu(lambda: scene.render(camera, encoded, 1, 32)) for _ in range(repeats)]
    print(f"tile costs: {scene_path.name} {w}x{h}, {samples} spp, on one thread: "
          f"{', '.join(f'{s:.2f}' for s in renders)} s of CPU", flush=True)

    rows, cols = math.ceil(h / c), math.ceil(w / c)
    cells = np.zeros((rows, cols))
    for j in range(rows):
        for i in range(cols):
            x, y = i * c, j * c
            cw, ch = min(c, w - x), min(c, h - y)
            cells[j, i] = _cpu(lambda: scene.render_tile(camera, encoded, x, y, cw, ch)) / (cw * ch)
    cost_map = cells / cells.mean()

    preview = statistics.median(_cpu(lambda: scene.render_tile(camera, encoded, 0, 0, w, h, scale=PREVIEW_SCALE))
                                for _ in range(repeats))
    full = statistics.median(renders)
    preview_factor = (preview / math.ceil(w / PREVIEW_SCALE) / math.ceil(h / PREVIEW_SCALE)) / (full / (w * h))

    one = [_cpu(lambda: scene.render_tile(camera, encoded, w // 2, h // 2, 1, 1)) for _ in range(50)]
    color = np.asarray(scene.render_tile(camera, encoded, 0, 0, 256 // scale, 256 // scale))
    encode = statistics.median(_cpu(lambda: rtcore.encode_srgb8(color, encoded)) for _ in range(20))
    pixels = w * h
    return RenderCosts(scene=scene_path.name, width=width, height=height, measured_scale=scale,
                       pixel_s=Spread.of([r / pixels for r in renders]), render_s=Spread.of(renders),
                       cost_map=cost_map, cell=cell, preview_factor=preview_factor, tile_s=Spread.of(one),
                       encode_s_per_pixel=encode / color.shape[0] / color.shape[1], pixel_rays=pixel_rays)
