"""services/tile_tasks.py: a tile task answers an rt.TileResult; a preview's
layers travel in it as arrays, and a tile that takes its preview's pixels from
them is the tile traced in full. A worker that does not see the data folder
fetches the scene and answers the layers it would have written."""

import json

import numpy as np
import pytest
import rtcore
from rt import job_pb2

from app.core.proto import normalize
from app.services import data_access, layer_files, tile_tasks
from app.services.tile_plan import TileSpec


class Worker:
    """What render_tile asks of its Dask worker."""

    def __init__(self):
        self.events = []

    def log_event(self, topic, message):
        self.events.append((topic, message))

    def get_current_task(self):
        return "tile-key"


@pytest.fixture
def run(monkeypatch, tmp_path, scenes_dir):
    worker = Worker()
    monkeypatch.setattr(tile_tasks, "get_worker", lambda: worker)
    (tmp_path / "jobs").mkdir()
    (tmp_path / data_access.FOLDER_ID_FILE).write_text("this-folder")
    scene = scenes_dir / "cornell.obj"
    request = normalize(job_pb2.JobRequest, json.dumps({
        "scene_id": "s", "camera": {"position": [0, 1, 3.5], "target": [0, 1, 0]},
        "settings": {"width": 64, "height": 64}, "outputs": ["DEPTH", "BVH_COST"]}),
        lambda _: rtcore.Scene.load(str(scene)))
    layers_dir = layer_files.create(tmp_path, 64, 64, 32, tile_tasks.aux_names(request))

    def render(spec, preview=None, run_id="run", folder_id="this-folder"):
        access = data_access.DataAccess(str(tmp_path), folder_id, "http://server", "secret")
        return tile_tasks.render_tile(access, "cornell-hash", str(scene), request.SerializeToString(), "job", run_id,
                                      str(layers_dir), spec, *([preview] if preview is not None else []))
    render.worker = worker
    render.layers_dir = layers_dir
    render.scene = scene
    return render


@pytest.mark.parametrize("array", [
    np.arange(24, dtype=np.float32).reshape(2, 4, 3),
    np.arange(8, dtype=np.float32).reshape(2, 4),
    np.arange(16, dtype=np.uint32).reshape(2, 4, 2),
])
def test_a_layer_travels_as_its_array(array):
    layer = job_pb2.Layer.FromString(tile_tasks.layer_message("depth", array).SerializeToString())
    back = tile_tasks.layer_array(layer)
    assert layer.name == "depth" and back.dtype == array.dtype and np.array_equal(back, array)


def test_a_preview_answers_its_layers_and_a_full_tile_only_its_message(run):
    preview = run(TileSpec(0, 0, 0, 64, 64, 8, 0))
    assert isinstance(preview, job_pb2.TileResult)
    assert [layer.name for layer in preview.layers] == ["color", "depth", "bvh_cost"]
    assert [tuple(layer.shape)[:2] for layer in preview.layers] == [(8, 8)] * 3
    message = job_pb2.TileStreamMessage.FromString(preview.message)
    assert message.tile.scale == 8 and len(message.tile.pixels) == 8 * 8 * 4
    assert preview.rays >= 64 and preview.samples == 64 and preview.started > 0 and preview.seconds > 0
    full = run(TileSpec(1, 0, 0, 32, 32, 1, 0))
    assert not full.layers and job_pb2.TileStreamMessage.FromString(full.message).tile.region.w == 32
    assert run.worker.events == [(tile_tasks.TILE_STARTED_TOPIC, "tile-key")] * 2


def test_a_tile_taking_its_previews_pixels_is_the_tile_traced_in_full(run):
    preview_spec = TileSpec(0, 0, 0, 64, 64, 8, 0)
    preview = job_pb2.TileResult.FromString(run(preview_spec).SerializeToString())  # as a real cluster sends it
    spec = TileSpec(1, 32, 32, 32, 32, 1, 0, preview_spec)
    taking = run(spec, preview)
    traced = run(TileSpec(1, 32, 32, 32, 32, 1, 0))
    assert taking.message == traced.message
    assert taking.samples == traced.samples - 4 * 4, "the preview's 16 pixels of the tile were not traced again"


def test_a_stopped_run_answers_none(run):
    tile_tasks.stop_run("stopped-run")
    assert run(TileSpec(1, 0, 0, 32, 32, 1, 0), run_id="stopped-run") is None


def test_a_worker_without_the_data_folder_fetches_the_scene_and_answers_the_layers(run, monkeypatch):
    fetched = []

    def fetch_scene(access, sha256):
        fetched.append((access.server_url, access.secret, sha256))
        return rtcore.Scene.load(str(run.scene))

    monkeypatch.setattr(tile_tasks, "fetch_scene", fetch_scene)
    monkeypatch.setattr(tile_tasks, "get_scene", lambda sha256, source: source() if callable(source) else
                        rtcore.Scene.load(str(source)))
    spec = TileSpec(1, 32, 0, 32, 32, 1, 0)
    shared = run(spec)
    assert shared.shared_folder and not shared.layers and not fetched
    written = {name: layer_files.load(run.layers_dir.parent, name, layer_files.PARTIAL) for name in ("color", "depth", "bvh_cost")}
    elsewhere = run(spec, folder_id="another-folder")
    assert fetched == [("http://server", "secret", "cornell-hash")]
    assert not elsewhere.shared_folder and elsewhere.message == shared.message
    assert [layer.name for layer in elsewhere.layers] == ["color", "depth", "bvh_cost"]
    for layer in elsewhere.layers:
        expected = written[layer.name][0:32, 32:64]
        assert np.array_equal(tile_tasks.layer_array(layer).reshape(expected.shape), expected), layer.name
