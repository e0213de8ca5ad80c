"""The retention policy (RT_KEEP_JOBS, RT_KEEP_DAYS): jobs that have ended go
with their files once they are neither among the newest nor recent enough;
pinned jobs, references and running jobs never do."""

import sqlite3
import time

import pytest
from fastapi.testclient import TestClient

from app.main import create_app
from service import service_settings
from stream_reader import wait_for


@pytest.fixture
def service(tmp_path, cornell_zip, request):
    settings = service_settings(tmp_path, **request.param)
    with TestClient(create_app(settings)) as client:
        scene = client.post("/api/scenes", files={"file": ("cornell.zip", cornell_zip)}).json()["id"]
        yield client, scene


def render(client, scene_id, **settings) -> str:
    job = client.post("/api/jobs", json={"scene_id": scene_id,
                                         "settings": {"width": 32, "height": 24, **settings}}).json()
    assert wait_for(client, job["id"])["state"] == "DONE"
    return job["id"]


def kept(client, job_id) -> bool:
    present = client.get(f"/api/jobs/{job_id}").status_code == 200
    assert present == (client.app.state.settings.jobs_dir / job_id).exists(), "the files go with the record"
    return present


@pytest.mark.parametrize("service", [{"keep_jobs": 2}], indirect=True)
def test_the_newest_jobs_pinned_ones_and_references_are_kept(service):
    client, scene = service
    pinned = render(client, scene)
    assert client.put(f"/api/jobs/{pinned}/pin").json()["pinned"] is True
    reference = render(client, scene)
    assert client.put(f"/api/scenes/{scene}/references/{reference}").status_code == 200
    plain = render(client, scene)
    unpinned = render(client, scene)
    assert client.put(f"/api/jobs/{unpinned}/pin").status_code == 200
    assert client.delete(f"/api/jobs/{unpinned}/pin").json()["pinned"] is False
    newest = [render(client, scene), render(client, scene)]
    assert not kept(client, plain) and not kept(client, unpinned)
    assert kept(client, pinned) and kept(client, reference) and all(kept(client, j) for j in newest)
    listed = [j["id"] for j in client.get("/api/jobs").json()["jobs"]]
    assert listed == [*reversed(newest), reference, pinned]


@pytest.mark.parametrize("service", [{"keep_jobs": 1}], indirect=True)
def test_a_running_job_is_never_removed(service):
    client, scene = service
    slow = client.post("/api/jobs", json={"scene_id": scene, "interactive": False, "settings": {
        "width": 256, "height": 256, "samples_per_pixel": 4096}}).json()["id"]
    first, second = render(client, scene), render(client, scene)
    assert client.get(f"/api/jobs/{slow}").json()["state"] in ("QUEUED", "RUNNING")
    assert not kept(client, first) and kept(client, second)
    assert client.delete(f"/api/jobs/{slow}").json()["state"] == "CANCELLED"


@pytest.mark.parametrize("service", [{"keep_days": 1}], indirect=True)
def test_jobs_older_than_the_days_go(service):
    client, scene = service
    old, recent = render(client, scene), render(client, scene)
    with sqlite3.connect(client.app.state.settings.database) as db:
        db.execute("UPDATE jobs SET created_at = ? WHERE id = ?", (time.time() - 2 * 86400, old))
    render(client, scene)  # a job's end applies the policy, as the hourly pass does
    assert not kept(client, old) and kept(client, recent)


@pytest.mark.parametrize("service", [{}], indirect=True)
def test_without_a_policy_every_job_is_kept_and_pins_need_a_job(service):
    client, scene = service
    jobs = [render(client, scene) for _ in range(3)]
    assert all(kept(client, j) for j in jobs)
    assert client.put("/api/jobs/nojob/pin").status_code == 404


def test_a_bad_policy_stops_the_server_naming_it(monkeypatch):
    from app.core.config import Settings
    monkeypatch.setenv("RT_KEEP_JOBS", "-1")
    with pytest.raises(SystemExit, match="RT_KEEP_JOBS='-1': expected an integer of at least 0"):
        Settings()
    monkeypatch.setenv("RT_KEEP_JOBS", "3")
    monkeypatch.setenv("RT_KEEP_DAYS", "soon")
    with pytest.raises(SystemExit, match="RT_KEEP_DAYS='soon': expected a number"):
        Settings()
    monkeypatch.setenv("RT_KEEP_DAYS", "2.5")
    assert (Settings().keep_jobs, Settings().keep_days) == (3, 2.5)
