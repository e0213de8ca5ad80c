"""DELETE /api/jobs/{id}: a queued or running job is cancelled (as ever); one
that has ended goes with its files; a view's reference only once unmarked.
/api/health says how much the data folder holds and its disk has left."""

import time

import pytest
from fastapi.testclient import TestClient

from app.main import create_app
from service import service_settings
from stream_reader import wait_for


@pytest.fixture(scope="module")
def own(tmp_path_factory, cornell_zip):
    """A service of its own: its data folder's size is this test's alone."""
    with TestClient(create_app(service_settings(tmp_path_factory.mktemp("deletion")))) as client:
        scene = client.post("/api/scenes", files={"file": ("cornell.zip", cornell_zip)})
        assert scene.status_code == 201, scene.text
        yield client, scene.json()["id"]


def render(client, scene_id, **settings) -> dict:
    body = {"scene_id": scene_id, "settings": {"width": 96, "height": 72, **settings},
            "outputs": ["DEPTH", "NORMAL", "ALBEDO"]}
    job = client.post("/api/jobs", json=body).json()
    return wait_for(client, job["id"])


def test_a_done_job_goes_with_its_files_and_the_data_folder_shrinks(own):
    client, scene_id = own
    job = render(client, scene_id)
    assert job["state"] == "DONE"
    folder = client.app.state.settings.jobs_dir / job["id"]
    assert client.get(f"/api/jobs/{job['id']}/image.exr").status_code == 200
    before = client.get("/api/health").json()
    # uint64 fields: strings in proto's JSON.
    assert int(before["data_bytes"]) > 0 and int(before["free_bytes"]) > 0
    answer = client.delete(f"/api/jobs/{job['id']}")
    assert answer.status_code == 204 and answer.content == b""
    assert not folder.exists()
    assert client.get(f"/api/jobs/{job['id']}").status_code == 404
    assert client.get(f"/api/jobs/{job['id']}/image.png").status_code == 404
    assert job["id"] not in [j["id"] for j in client.get("/api/jobs").json()["jobs"]]
    after = client.get("/api/health").json()
    # The image.exr and the layers went: at least the colour's floats.
    assert int(before["data_bytes"]) - int(after["data_bytes"]) >= 96 * 72 * 3 * 4
    assert client.delete(f"/api/jobs/{job['id']}").status_code == 404


def test_a_running_job_is_cancelled_first_then_deleted(own):
    client, scene_id = own
    job = client.post("/api/jobs", json={"scene_id": scene_id, "settings": {
        "width": 512, "height": 512, "samples_per_pixel": 1024}}).json()
    cancelled = client.delete(f"/api/jobs/{job['id']}")
    assert cancelled.status_code == 200 and cancelled.json()["state"] == "CANCELLED"
    assert client.get(f"/api/jobs/{job['id']}").json()["state"] == "CANCELLED", "the record stays"
    assert client.delete(f"/api/jobs/{job['id']}").status_code == 204
    assert client.get(f"/api/jobs/{job['id']}").status_code == 404


def test_a_reference_is_kept_until_it_is_unmarked(own):
    client, scene_id = own
    job = render(client, scene_id)
    assert client.put(f"/api/scenes/{scene_id}/references/{job['id']}").status_code == 200
    refused = client.delete(f"/api/jobs/{job['id']}")
    assert refused.status_code == 409 and "reference" in refused.json()["detail"]
    assert f"/api/scenes/{scene_id}/references/{job['id']}" in refused.json()["detail"]
    assert client.get(f"/api/jobs/{job['id']}/image.png").status_code == 200, "nothing was removed"
    assert client.delete(f"/api/scenes/{scene_id}/references/{job['id']}").status_code == 200
    assert client.delete(f"/api/jobs/{job['id']}").status_code == 204


def test_the_openapi_documents_both_answers(own):
    client, _ = own
    answers = client.get("/openapi.json").json()["paths"]["/api/jobs/{job_id}"]["delete"]["responses"]
    assert {"200", "204", "409"} <= set(answers)
