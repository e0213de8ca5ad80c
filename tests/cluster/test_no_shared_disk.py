"""Workers that cannot see the server's data folder (an empty folder of their
own mounted at its path, another working directory): they fetch each scene from the server by its content hash
and send their tiles' layers back; jobs complete with the images a local
render gives, a killed worker included, and the job record says which way
the tiles came."""

import io
import os

import numpy as np
import pytest
from google.protobuf.json_format import ParseDict
from PIL import Image
from rt import job_pb2, render_pb2

from topology import expected_png, started, wait_until

if os.geteuid() != 0:
    pytest.skip("a mount namespace for the workers needs root (as make test runs on CI)", allow_module_level=True)


@pytest.fixture(scope="module")
def service(tmp_path_factory):
    yield from started(tmp_path_factory, shared_folder=False)


def dask_run(topology, function):
    from distributed import Client

    with Client(topology.env["RT_SCHEDULER"], timeout="20s") as dask_client:
        return dask_client.run(function)


def wait_for_end(client, job_id: str) -> dict:
    return wait_until(lambda: (j := client.get(f"/api/jobs/{job_id}").json())["state"] in
                      ("DONE", "FAILED", "CANCELLED") and j, 180, "the job to end")


def upload(client, path):
    with open(path, "rb") as f:
        answer = client.post("/api/scenes", files={"file": (path.name, f)})
    assert answer.status_code == 201, answer.text
    return answer.json()


def test_the_workers_see_a_folder_of_their_own_at_the_data_folders_path(service):
    topology, _ = service
    data_dir = str(topology.data_dir)
    assert (topology.data_dir / "scenes").is_dir() and (topology.data_dir / "folder-id").is_file()
    seen = dask_run(topology, lambda: (os.listdir(data_dir), os.access(data_dir, os.W_OK), os.getcwd()))
    assert len(seen) == 2
    for files, writable, cwd in seen.values():
        assert files == [] and writable and cwd == str(topology.worker_home)


def test_a_job_renders_over_the_network_with_the_local_image_and_layers(service, scenes_dir):
    topology, client = service
    scene = upload(client, scenes_dir / "teapot.glb")
    settings = {"width": 320, "height": 240, "samples_per_pixel": 4}
    job = client.post("/api/jobs", json={"scene_id": scene["id"], "settings": settings, "outputs": ["DEPTH"],
                                         "interactive": True}).json()
    done = wait_for_end(client, job["id"])
    assert done["state"] == "DONE", done["error"]
    # Its full-resolution tiles: all but the preview pass's one tile.
    assert done["passes"] == 2 and done["tiles_via_network"] == done["tiles_total"] - 1
    assert done["tiles_via_shared_folder"] == 0
    request = ParseDict(done["request"], job_pb2.JobRequest())
    png = np.asarray(Image.open(io.BytesIO(client.get(f"/api/jobs/{job['id']}/image.png").content)).convert("RGBA"))
    assert np.array_equal(png, expected_png(scenes_dir / "teapot.glb", done["request"]["camera"], request.settings))
    import rtcore

    local = rtcore.Scene.load(str(scenes_dir / "teapot.glb")).render_tile(
        request.camera.SerializeToString(), request.settings.SerializeToString(), 0, 0, 320, 240, aux=["depth"])
    layer = job_pb2.Layer.FromString(client.get(f"/api/jobs/{job['id']}/layers/depth").content)
    depth = np.frombuffer(layer.data, np.dtype(layer.dtype)).reshape(tuple(layer.shape))
    np.testing.assert_array_equal(depth.reshape(local["depth"].shape), local["depth"])


def test_a_killed_worker_costs_only_its_tiles_without_a_shared_folder(service, scenes_dir):
    topology, client = service
    scene = upload(client, scenes_dir / "dragon_3.glb")
    settings = {"width": 640, "height": 480, "max_depth": 3, "light_samples": 4, "samples_per_pixel": 16}
    job = client.post("/api/jobs", json={"scene_id": scene["id"], "settings": settings}).json()
    wait_until(lambda: client.get(f"/api/jobs/{job['id']}").json()["tiles_done"] >= 1, 60, "the first tile")
    victim = topology.workers[0]
    victim.kill()
    victim.wait(10)
    at_kill = client.get(f"/api/jobs/{job['id']}").json()
    assert at_kill["tiles_done"] < at_kill["tiles_total"], "the job ended before the worker was killed"
    done = wait_for_end(client, job["id"])
    assert done["state"] == "DONE", done["error"]
    assert 0 < done["tiles_via_network"] <= done["tiles_total"] and done["tiles_via_shared_folder"] == 0
    png = np.asarray(Image.open(io.BytesIO(client.get(f"/api/jobs/{job['id']}/image.png").content)).convert("RGBA"))
    reference = expected_png(scenes_dir / "dragon_3.glb", done["request"]["camera"],
                             render_pb2.RenderSettings(**settings))
    assert np.array_equal(png, reference)
