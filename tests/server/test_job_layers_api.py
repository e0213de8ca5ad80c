"""/api/jobs/{id}/layers/{name}: a done job's linear layers, whole, as the
viewer's image view reads them (a serialized rt.Layer of float32)."""

import io

import numpy as np
import rtcore
from PIL import Image
from app.services import layer_files
from rt import job_pb2

from stream_reader import wait_for


def layer_of(client, job_id: str, name: str) -> tuple[job_pb2.Layer, np.ndarray]:
    response = client.get(f"/api/jobs/{job_id}/layers/{name}")
    assert response.status_code == 200, response.text
    assert response.headers["content-type"] == "application/x-protobuf"
    layer = job_pb2.Layer.FromString(response.content)
    assert layer.name == name and layer.dtype == "<f4"
    return layer, np.frombuffer(layer.data, "<f4").reshape(tuple(layer.shape))


def test_every_layer_is_the_saved_floats_with_the_exr_channel_names(client, cornell_id):
    body = {"scene_id": cornell_id, "settings": {"width": 40, "height": 30, "exposure": 1.5},
            "outputs": ["DEPTH", "NORMAL", "ALBEDO", "BVH_COST", "ALPHA"]}
    job = client.post("/api/jobs", json=body).json()
    assert wait_for(client, job["id"])["state"] == "DONE"
    folder = client.app.state.settings.jobs_dir / job["id"]
    expected_channels = {"color": ["R", "G", "B"], "depth": ["depth.Z"], "normal": ["normal.X", "normal.Y", "normal.Z"],
                         "albedo": ["albedo.R", "albedo.G", "albedo.B"],
                         "bvh_cost": ["bvh_cost.nodes", "bvh_cost.triangles"], "alpha": ["A"]}
    for name, channels in expected_channels.items():
        layer, values = layer_of(client, job["id"], name)
        assert list(layer.channels) == channels
        saved = np.asarray(layer_files.load(folder, name)).reshape(30, 40, len(channels))
        assert values.shape == (30, 40, len(channels))
        assert np.array_equal(values, saved), name
    _, color = layer_of(client, job["id"], "color")
    # Linear, before the job's exposure: only image.png and the tiles are exposed.
    assert 0.05 < color.max() and np.array_equal(rtcore.encode_srgb8(np.ascontiguousarray(color), '{"exposure": 1.5}'),
                                                 np.asarray(_png(client, job["id"])))


def _png(client, job_id):
    return Image.open(io.BytesIO(client.get(f"/api/jobs/{job_id}/image.png").content)).convert("RGBA")


def test_unknown_or_missing_layers_are_named_in_a_404(client, cornell_id):
    job = client.post("/api/jobs", json={"scene_id": cornell_id, "settings": {"width": 16, "height": 12}}).json()
    assert wait_for(client, job["id"])["state"] == "DONE"
    missing = client.get(f"/api/jobs/{job['id']}/layers/depth")
    assert missing.status_code == 404 and "no depth layer" in missing.json()["detail"]
    unknown = client.get(f"/api/jobs/{job['id']}/layers/..%2Fsecret")
    assert unknown.status_code == 404
    wrong = client.get(f"/api/jobs/{job['id']}/layers/colour")
    assert wrong.status_code == 404 and "one of: color, noisy, depth" in wrong.json()["detail"]
    nobody = client.get("/api/jobs/nojob/layers/color")
    assert nobody.status_code == 404 and "nojob" in nobody.json()["detail"]
