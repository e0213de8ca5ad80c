"""A full data folder (a small tmpfs): uploads, jobs, pins and images made on
demand answer 507 naming it, a job whose tiles find no room fails saying so,
nothing stored before changes, and the server stays up and works again once
there is room."""

import hashlib
import os
import sqlite3
import subprocess
import time
from pathlib import Path

import pytest
from fastapi.testclient import TestClient
from rt import job_pb2

from app.main import create_app
from service import service_settings

if os.geteuid() != 0:
    pytest.skip("mounting a small tmpfs needs root (as make test runs on CI)", allow_module_level=True)


@pytest.fixture(scope="module")
def disk(tmp_path_factory):
    mount = tmp_path_factory.mktemp("small-disk")
    subprocess.run(["mount", "-t", "tmpfs", "-o", "size=24m", "rt-test-full", str(mount)], check=True)
    try:
        yield mount
    finally:
        subprocess.run(["umount", "-l", str(mount)], check=False)


@pytest.fixture(scope="module")
def client(disk):
    with TestClient(create_app(service_settings(disk / "data"))) as client:
        yield client


def fill(disk: Path) -> Path:
    filler = disk / "filler"
    with open(filler, "wb") as f:
        try:
            while True:
                f.write(b"\0" * (1 << 16))
                f.flush()
        except OSError:
            pass
    return filler


def stored_digest(data: Path) -> str:
    """Every stored file but the job database (whose pages SQLite may touch)."""
    digest = hashlib.sha256()
    for path in sorted(data.rglob("*")):
        if path.is_file() and not path.name.startswith("jobs.sqlite"):
            digest.update(str(path.relative_to(data)).encode() + path.read_bytes())
    return digest.hexdigest()


def wait_end(client, job_id):
    for _ in range(600):
        job = client.get(f"/api/jobs/{job_id}").json()
        if job["state"] in ("DONE", "FAILED", "CANCELLED"):
            return job
        time.sleep(0.05)
    raise AssertionError("the job did not end")


def assert_full(answer):
    assert answer.status_code == 507, answer.text
    assert "data folder is full" in answer.json()["detail"]


def test_a_full_data_folder_is_a_507_and_loses_nothing(client, disk, scenes_dir):
    with open(scenes_dir / "teapot.glb", "rb") as f:
        scene = client.post("/api/scenes", files={"file": ("teapot.glb", f)}).json()["id"]
    done = wait_end(client, client.post("/api/jobs", json={"scene_id": scene, "settings": {
        "width": 64, "height": 48}}).json()["id"])
    assert done["state"] == "DONE"
    data = disk / "data"
    before = stored_digest(data)
    filler = fill(disk)
    try:
        with open(scenes_dir / "teapot.glb", "rb") as f:
            assert_full(client.post("/api/scenes", files={"file": ("again.glb", f)}))
        assert_full(client.post("/api/jobs", json={"scene_id": scene, "settings": {"width": 64, "height": 48}}))
        assert_full(client.put(f"/api/jobs/{done['id']}/pin"))
        assert_full(client.get(f"/api/jobs/{done['id']}/image.exr"))
        assert client.get("/api/health").status_code == 200
        assert len(client.get("/api/scenes").json()["scenes"]) == 1
        assert stored_digest(data) == before
    finally:
        filler.unlink()
    again = wait_end(client, client.post("/api/jobs", json={"scene_id": scene, "settings": {
        "width": 64, "height": 48}}).json()["id"])
    assert again["state"] == "DONE"
    assert client.get(f"/api/jobs/{done['id']}/image.exr").status_code == 200


def test_a_job_whose_tiles_find_no_room_fails_saying_so(client, disk, scenes_dir):
    scene = client.get("/api/scenes").json()["scenes"][0]["id"]
    filler = fill(disk)
    try:
        # Room for the record, none for 1024 x 1024 floats: the tiles' writes fail.
        filler.write_bytes(b"\0" * max(0, filler.stat().st_size - (1 << 20)))
        posted = client.post("/api/jobs", json={"scene_id": scene, "outputs": ["DEPTH", "NORMAL", "ALBEDO"],
                                                "settings": {"width": 1024, "height": 1024}})
        assert posted.status_code == 202, posted.text
        failed = wait_end(client, posted.json()["id"])
        assert failed["state"] == "FAILED" and "data folder is full" in failed["error"], failed["error"]
        assert not (disk / "data" / "jobs" / failed["id"]).exists(), "the failed job's files went"
        assert client.get("/api/health").status_code == 200
    finally:
        filler.unlink()


def test_a_job_that_ends_when_its_record_finds_no_room_is_still_seen_ended(client, monkeypatch):
    """SQLite refuses the final record: the job is answered as ended from
    memory, never left running for everyone to wait on, and saved later."""
    scene = client.get("/api/scenes").json()["scenes"][0]["id"]
    store = client.app.state.jobs._store
    save = store.save

    def save_but_not_the_end(job):
        if job.state in (job_pb2.DONE, job_pb2.FAILED, job_pb2.CANCELLED):
            raise sqlite3.OperationalError("database or disk is full")
        save(job)

    monkeypatch.setattr(store, "save", save_but_not_the_end)
    job = wait_end(client, client.post("/api/jobs", json={"scene_id": scene, "settings": {
        "width": 64, "height": 48}}).json()["id"])
    assert job["state"] == "DONE"
    assert store.get(job["id"]).state in (job_pb2.QUEUED, job_pb2.RUNNING), "the store still holds it running"
    assert [j["state"] for j in client.get("/api/jobs").json()["jobs"] if j["id"] == job["id"]] == ["DONE"]
    monkeypatch.setattr(store, "save", save)
    wait_end(client, client.post("/api/jobs", json={"scene_id": scene, "settings": {
        "width": 64, "height": 48}}).json()["id"])  # its end saves the one kept in memory
    assert store.get(job["id"]).state == job_pb2.DONE
