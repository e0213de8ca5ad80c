"""Restarting the service loses no scene, job record or image, and leaves no
job showing 'running' forever."""

import time

from fastapi.testclient import TestClient

from app.main import create_app
from service import service_settings
from stream_reader import wait_for


def test_restart_keeps_scenes_jobs_and_images_and_resumes_running_jobs(tmp_path, scenes_dir):
    settings = service_settings(tmp_path)
    with TestClient(create_app(settings)) as first:
        with open(scenes_dir / "bunny.glb", "rb") as f:
            scene_id = first.post("/api/scenes", files={"file": ("bunny.glb", f)}).json()["id"]
        finished = first.post("/api/jobs", json={"scene_id": scene_id, "settings": {"width": 64, "height": 48}}).json()
        assert wait_for(first, finished["id"])["state"] == "DONE"
        image = first.get(f"/api/jobs/{finished['id']}/image.png").content
        big = first.post("/api/jobs", json={"scene_id": scene_id,
                                            "settings": {"width": 2048, "height": 1536}}).json()
        time.sleep(0.3)
        assert first.get(f"/api/jobs/{big['id']}").json()["state"] in ("QUEUED", "RUNNING")
    # The server stopped mid-job. A new one on the same data folder:
    with TestClient(create_app(settings)) as second:
        assert second.get(f"/api/scenes/{scene_id}").json()["name"] == "bunny.glb"
        again = second.get(f"/api/jobs/{finished['id']}").json()
        assert again["state"] == "DONE" and again["id"] == finished["id"]
        assert second.get(f"/api/jobs/{finished['id']}/image.png").content == image
        resumed = wait_for(second, big["id"], timeout=180)
        assert resumed["state"] == "DONE" and resumed["tiles_done"] == resumed["tiles_total"]
        # A late viewer of a job finished before the restart gets the whole image, then the end.
        ids = [j["id"] for j in second.get("/api/jobs").json()["jobs"]]
        assert ids.index(big["id"]) < ids.index(finished["id"]), "newest first"


def test_a_job_whose_scene_vanished_while_down_fails_with_the_reason(tmp_path, scenes_dir):
    settings = service_settings(tmp_path)
    with TestClient(create_app(settings)) as first:
        with open(scenes_dir / "teapot.glb", "rb") as f:
            scene_id = first.post("/api/scenes", files={"file": ("teapot.glb", f)}).json()["id"]
        job = first.post("/api/jobs", json={"scene_id": scene_id,
                                            "settings": {"width": 2048, "height": 2048, "light_samples": 256}}).json()
        time.sleep(0.2)
    import shutil

    shutil.rmtree(settings.scenes_dir / scene_id)
    with TestClient(create_app(settings)) as second:
        failed = second.get(f"/api/jobs/{job['id']}").json()
        assert failed["state"] == "FAILED" and "scene is gone" in failed["error"]


def test_sample_scenes_are_added_once(tmp_path, scenes_dir):
    import shutil

    samples = tmp_path / "samples"
    samples.mkdir()
    for name in ("cornell.obj", "cornell.mtl", "cornell.rt.json", "teapot.glb"):
        shutil.copy(scenes_dir / name, samples / name)
    settings = service_settings(tmp_path / "data", samples_dir=samples)
    for _ in range(2):  # a restart does not add them again
        with TestClient(create_app(settings)) as client:
            scenes = {s["name"]: s for s in client.get("/api/scenes").json()["scenes"]}
            assert sorted(scenes) == ["cornell.obj", "teapot.glb"]
            assert scenes["cornell.obj"]["lights"] and not scenes["cornell.obj"]["warnings"]


def test_images_of_jobs_saved_before_the_layer_files_are_still_served(tmp_path):
    """A job done by an earlier version kept its layers in one layers.npz."""
    import numpy as np
    from app.services import layer_files
    from app.services.job_image import output_file

    color = np.random.default_rng(1).random((6, 8, 3), dtype=np.float32)
    np.savez(tmp_path / layer_files.LEGACY_FILE, color=color, depth=np.ones((6, 8, 1), np.float32))
    assert layer_files.names(tmp_path) == ["color", "depth"]
    np.testing.assert_array_equal(layer_files.load(tmp_path, "color"), color)
    assert output_file(tmp_path, "image.png", b"").is_file()
    assert output_file(tmp_path, "depth.png", b"").is_file()
