"""What a Dask worker runs: one tile of one job.

Workers import this module by name, so it stays small and depends only on
rtcore, the scene cache, the tile plan, the layer files and the data access.
The arguments are plain values (how to reach the job's data, the scene's path
and content hash, the serialized request, the job and its run, the job's layer
folder, the tile) so that any worker can run any tile: one that sees the
server's data folder reads the scene and writes the tile's layers there, any
other fetches the scene from the server and sends the layers back
(services/data_access.py).
"""

from __future__ import annotations

import atexit
import threading
import time
from collections import OrderedDict

import numpy as np
import rtcore
from distributed import get_worker
from rt import job_pb2, render_pb2

from . import layer_files
from .data_access import DataAccess, sees_data_folder
from .layer_files import layer_array, layer_message
from .scene_cache import get_scene
from .scene_fetch import fetch_scene
from .tile_plan import TileSpec


def aux_names(request: job_pb2.JobRequest) -> list[str]:
    """The auxiliary layers a job's tiles render: those asked for, and the
    denoiser's guides (albedo and normal) when it is denoised."""
    names = [job_pb2.AuxOutput.Name(o).lower() for o in request.outputs]
    if request.settings.denoise != render_pb2.NO_DENOISER:
        names += [guide for guide in ("normal", "albedo") if guide not in names]
    return names


# Workers announce each tile they start on this topic; the server forwards it
# to the job's viewers, who outline the tiles being rendered.
TILE_STARTED_TOPIC = "rt-tile-started"

# Dask cannot interrupt a running task, so a worker keeps a stop source per run
# of a job it has seen (the newest KEPT_STOPS; a job resumed after a restart is
# a new run): stop_run, which the server runs on every worker when a job ends
# early, makes the run's tiles stop at their next pixel, or return at once.
KEPT_STOPS = 1024
_stops: OrderedDict[str, rtcore.StopSource] = OrderedDict()
_stops_lock = threading.Lock()
# Dropped at exit, as scene_cache's scenes are.
atexit.register(_stops.clear)


def _stop_source(run_id: str) -> rtcore.StopSource:
    with _stops_lock:
        source = _stops.get(run_id)
        if source is None:
            source = _stops[run_id] = rtcore.StopSource()
            while len(_stops) > KEPT_STOPS:
                _stops.popitem(last=False)
        return source


def stop_run(run_id: str) -> None:
    _stop_source(run_id).request_stop()


def render_tile(access: DataAccess, scene_hash: str, scene_path: str, request_bytes: bytes, job_id: str, run_id: str,
                layers_dir: str, spec: TileSpec, preview: job_pb2.TileResult | None = None) -> job_pb2.TileResult | None:
    """Renders one tile, answered as an rt.TileResult. A full-resolution tile
    writes its layers into the job's layer files in `layers_dir` when this
    worker sees the data folder, and answers them otherwise; a preview answers
    them, arrays of ceil(h/scale) x ceil(w/scale) pixels, for the tiles that
    take its pixels. Either answers the tile as the stream sends it
    to viewers (a serialized rt.TileStreamMessage, its RGBA8 pixels through
    the job's exposure and tone map), made here so that the server's event
    loop only forwards it; the rays traced and camera samples taken; and when
    the worker started and how long it took. `preview` is the result of
    spec.preview, whose pixels on its grid the tile takes instead of tracing
    them. None when the job's run was stopped (stop_run) before the tile was
    done."""
    started = time.time()
    stop = _stop_source(run_id)
    if stop.stop_requested:
        return None
    worker = get_worker()
    worker.log_event(TILE_STARTED_TOPIC, worker.get_current_task())
    request = job_pb2.JobRequest.FromString(request_bytes)
    shared = sees_data_folder(access)
    scene = get_scene(scene_hash, scene_path if shared else lambda: fetch_scene(access, scene_hash))
    camera = request.camera.SerializeToString()
    settings = request.settings.SerializeToString()
    known, stride = None, 0
    if spec.preview is not None and preview is not None:
        stride = spec.preview.scale
        window = spec.preview_window()
        known = {layer.name: np.ascontiguousarray(layer_array(layer)[window]) for layer in preview.layers}
    # With aux given (even empty) rtcore answers a dict that also counts the rays.
    try:
        layers = scene.render_tile(camera, settings, spec.x, spec.y, spec.w, spec.h, scale=spec.scale,
                                   aux=aux_names(request), known=known, known_stride=stride, stop=stop)
    except rtcore.RenderStopped:
        return None
    rays = int(layers.pop("rays"))
    samples = int(layers.pop("samples"))
    layers = {name: np.asarray(array) for name, array in layers.items()}
    tile = job_pb2.Tile(job=job_id, region=spec.region(), scale=spec.scale,
                        pixels=rtcore.encode_srgb8(layers["color"], settings).tobytes())
    if spec.scale == 1 and shared:
        layer_files.write_tile(layers_dir, spec.x, spec.y, layers)
    result = job_pb2.TileResult(message=job_pb2.TileStreamMessage(tile=tile).SerializeToString(), rays=rays,
                                samples=samples, started=started, shared_folder=shared)
    if spec.scale > 1 or not shared:
        result.layers.extend(layer_message(name, array) for name, array in layers.items())
    result.seconds = time.time() - started
    return result
