"""services/jobs.py: a finished job's stream once the server no longer holds it
(after a restart), and the whole-image tile built in one place."""

import asyncio
import io

import numpy as np
import pytest
from fastapi.testclient import TestClient
from PIL import Image
from rt import job_pb2

from app.main import create_app
from app.services.errors import Conflict
from app.services.jobs import final_image_stream, whole_image_tile
from service import service_settings
from stream_reader import read_stream, wait_for


def test_a_finished_job_streams_its_image_png_as_one_tile_after_a_restart(tmp_path, cornell_zip):
    settings = service_settings(tmp_path)
    with TestClient(create_app(settings)) as first:
        scene_id = first.post("/api/scenes", files={"file": ("cornell.zip", cornell_zip)}).json()["id"]
        job = first.post("/api/jobs", json={"scene_id": scene_id, "settings": {"width": 64, "height": 48}}).json()
        done = wait_for(first, job["id"])
    with TestClient(create_app(settings)) as second:
        assert second.app.state.jobs.stream(job["id"]) is None, "the restarted server holds no stream of it"
        messages = read_stream(second, job["id"])
        png = np.asarray(Image.open(io.BytesIO(second.get(f"/api/jobs/{job['id']}/image.png").content)).convert("RGBA"))
    assert [m.WhichOneof("message") for m in messages] == ["tile", "end"]
    tile = messages[0].tile
    region = tile.region
    assert (getattr(region, "pass"), region.x, region.y, region.w, region.h) == (done["passes"] - 1, 0, 0, 64, 48)
    assert tile.scale == 1 and tile.job == job["id"]
    assert np.array_equal(np.frombuffer(tile.pixels, np.uint8).reshape(48, 64, 4), png)
    assert messages[1].end.id == job["id"] and messages[1].end.state == job_pb2.DONE


def test_the_whole_image_tile_covers_the_image_at_full_scale():
    message = job_pb2.TileStreamMessage.FromString(whole_image_tile("j", 2, 5, 3, b"\x01" * 60))
    tile = message.tile
    assert (tile.job, getattr(tile.region, "pass"), tile.region.x, tile.region.y, tile.region.w, tile.region.h,
            tile.scale, tile.pixels) == ("j", 2, 0, 0, 5, 3, 1, b"\x01" * 60)


def test_a_job_without_its_image_streams_only_its_record():
    job = job_pb2.Job(id="j", state=job_pb2.FAILED, passes=2)
    assert [job_pb2.TileStreamMessage.FromString(m).WhichOneof("message")
            for m in final_image_stream(job, None)] == ["end"]
    rgba = np.zeros((3, 5, 4), np.uint8)
    first = job_pb2.TileStreamMessage.FromString(final_image_stream(job, rgba)[0])
    assert getattr(first.tile.region, "pass") == 1, "the last pass"


def test_the_images_of_a_job_not_done_are_a_conflict(client):
    running = job_pb2.Job(id="j", state=job_pb2.RUNNING)
    with pytest.raises(Conflict, match="job 'j' is running: its image exists once it is done"):
        asyncio.run(client.app.state.jobs.finished_file(running, "image.png"))


def test_deleting_a_scene_cancels_its_running_jobs_first(client, scenes_dir):
    with open(scenes_dir / "teapot.glb", "rb") as f:
        scene_id = client.post("/api/scenes", files={"file": ("teapot.glb", f)}).json()["id"]
    job = client.post("/api/jobs", json={"scene_id": scene_id, "settings": {
        "width": 1024, "height": 1024, "samples_per_pixel": 256}}).json()
    assert client.delete(f"/api/scenes/{scene_id}").status_code == 204
    ended = client.get(f"/api/jobs/{job['id']}").json()
    assert (ended["state"], ended["error"]) == ("CANCELLED", "the scene was deleted")
    assert client.get(f"/api/scenes/{scene_id}").status_code == 404


def _lose_the_scheduler():
    from distributed.client import FutureCancelledError

    raise FutureCancelledError("tile", "scheduler-connection-lost")


def _lose_the_results_worker():
    from distributed.comm.core import CommClosedError

    raise CommClosedError("in <TCP (closed) ConnectionPool.gather>: Stream is closed")


@pytest.mark.parametrize("loss", [_lose_the_scheduler, _lose_the_results_worker])
@pytest.mark.parametrize("losses, state", [(1, "DONE"), (3, "FAILED")])
def test_a_run_its_cluster_lost_runs_again_up_to_three_times(tmp_path, cornell_zip, monkeypatch, losses, state,
                                                              loss):
    """Dask cancels every future when the scheduler goes away: the job runs
    again from scratch once one is back, and fails after its third lost run."""
    with TestClient(create_app(service_settings(tmp_path))) as client:
        cluster = client.app.state.cluster
        submit, runs = cluster.submit, []

        def losing_submit(name, tasks, priorities):
            runs.append(name)
            if len(runs) <= losses:
                tasks = {key: (loss,) for key in tasks}
            return submit(name, tasks, priorities)

        monkeypatch.setattr(cluster, "submit", losing_submit)
        scene_id = client.post("/api/scenes", files={"file": ("cornell.zip", cornell_zip)}).json()["id"]
        job = wait_for(client, client.post("/api/jobs", json={"scene_id": scene_id, "settings": {
            "width": 64, "height": 48}}).json()["id"])
    assert job["state"] == state and len(runs) == min(losses + 1, 3)
    if state == "DONE":
        assert job["tiles_done"] == job["tiles_total"] and not job.get("error")
    else:
        assert "lost its Dask scheduler 3 times" in job["error"]
