"""What a Dask worker runs: one tile of one job.

Workers import this module by name, so it stays small and depends only on
rtcore, the scene cache, the tile plan and the layer files. The arguments are
plain values (the scene's path and content hash, the serialized request, the
job's layer folder, the tile) so that any worker that sees the shared data
folder can run any tile.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import rtcore
from distributed import get_worker
from rt import job_pb2

from . import layer_files
from .scene_cache import get_scene
from .tile_plan import TileSpec


def aux_names(request: job_pb2.JobRequest) -> list[str]:
    return [job_pb2.AuxOutput.Name(o).lower() for o in request.outputs]


# Workers announce each tile they start on this topic; the server forwards it
# to the job's viewers, who outline the tiles being rendered.
TILE_STARTED_TOPIC = "rt-tile-started"


def render_tile(scene_hash: str, scene_path: str, request_bytes: bytes, job_id: str, layers_dir: str,
                spec: TileSpec, preview: dict[str, Any] | None = None) -> dict[str, Any]:
    """Renders one tile. A full-resolution tile writes its layers into the
    job's layer files in `layers_dir`; a preview answers them, arrays of
    ceil(h/scale) x ceil(w/scale) pixels, for the tiles that take its pixels.
    Either answers the tile as the stream sends it to viewers (a serialized
    rt.TileStreamMessage, its RGBA8 pixels through the job's exposure and tone
    map), made here so that the server's event loop only forwards it; the rays
    traced and camera samples taken; and when the worker started and how long
    it took. `preview` is the result of spec.preview, whose pixels on its grid
    the tile takes instead of tracing them."""
    started = time.time()
    worker = get_worker()
    worker.log_event(TILE_STARTED_TOPIC, worker.get_current_task())
    request = job_pb2.JobRequest.FromString(request_bytes)
    scene = get_scene(scene_hash, scene_path)
    camera = request.camera.SerializeToString()
    settings = request.settings.SerializeToString()
    known, stride = None, 0
    if spec.preview is not None and preview is not None:
        stride = spec.preview.scale
        window = spec.preview_window()
        known = {name: np.ascontiguousarray(layer[window]) for name, layer in preview["layers"].items()}
    # With aux given (even empty) rtcore answers a dict that also counts the rays.
    layers = scene.render_tile(camera, settings, spec.x, spec.y, spec.w, spec.h, scale=spec.scale,
                               aux=aux_names(request), known=known, known_stride=stride)
    rays = int(layers.pop("rays"))
    samples = int(layers.pop("samples"))
    layers = {name: np.asarray(array) for name, array in layers.items()}
    tile = job_pb2.Tile(job=job_id, region=spec.region(), scale=spec.scale,
                        pixels=rtcore.encode_srgb8(layers["color"], settings).tobytes())
    if spec.scale == 1:
        layer_files.write_tile(layers_dir, spec.x, spec.y, layers)
    return {
        "layers": layers if spec.scale > 1 else None,
        "message": job_pb2.TileStreamMessage(tile=tile).SerializeToString(),
        "rays": rays,
        "samples": samples,
        "started": started,
        "seconds": time.time() - started,
    }
