"""Per-user quotas (RT_QUOTA_MB, RT_QUOTA_QUEUED_JOBS): what is over them is
refused with 413 or 429 naming the limit and the use, and GET /api/me shows
the use against them."""

import pytest
from fastapi.testclient import TestClient

from app.core.users import User
from app.main import create_app
from service import service_settings
from stream_reader import wait_for

ALICE = "alice-token-0123456789"
BOB = "bob-token-0123456789ab"
MB = 1 << 20


def as_user(token):
    return {"Authorization": f"Bearer {token}"}


@pytest.fixture
def service(tmp_path, request):
    settings = service_settings(tmp_path, users=(User("alice", ALICE), User("bob", BOB)), **request.param)
    with TestClient(create_app(settings)) as client:
        yield client


def upload(client, token, path):
    with open(path, "rb") as f:
        return client.post("/api/scenes", files={"file": (path.name, f)}, headers=as_user(token))


@pytest.mark.parametrize("service", [{"quota_bytes": 1 * MB}], indirect=True)
def test_uploads_past_the_byte_quota_are_refused_naming_it(service, scenes_dir):
    assert upload(service, ALICE, scenes_dir / "dragon_3.glb").status_code == 201  # 0.8 MB
    me = service.get("/api/me", headers=as_user(ALICE)).json()
    assert int(me["quota_bytes"]) == MB and 800_000 < int(me["stored_bytes"]) <= MB and me["scenes"] == 1
    refused = upload(service, ALICE, scenes_dir / "dragon_4.glb")  # 0.2 MB more: past 1 MB
    assert refused.status_code == 413, refused.text
    detail = refused.json()["detail"]
    assert "quota of 1.0 MB" in detail and "RT_QUOTA_MB" in detail and "you store 0.8 MB" in detail
    assert len(service.get("/api/scenes", headers=as_user(ALICE)).json()["scenes"]) == 1, "nothing kept"
    big = upload(service, ALICE, scenes_dir / "dragon_2.glb")  # 3.6 MB: stopped while streaming
    assert big.status_code == 413 and "RT_QUOTA_MB" in big.json()["detail"]
    # Bob's quota is his own.
    assert upload(service, BOB, scenes_dir / "dragon_4.glb").status_code == 201


@pytest.mark.parametrize("service", [{"quota_bytes": 1 * MB}], indirect=True)
def test_a_job_whose_output_would_pass_the_quota_is_refused(service, scenes_dir):
    scene = upload(service, ALICE, scenes_dir / "teapot.glb").json()["id"]
    refused = service.post("/api/jobs", json={"scene_id": scene, "settings": {"width": 1024, "height": 1024}},
                           headers=as_user(ALICE))
    assert refused.status_code == 413 and "this job's output (about 16.0 MB)" in refused.json()["detail"]
    small = service.post("/api/jobs", json={"scene_id": scene, "settings": {"width": 32, "height": 24}},
                         headers=as_user(ALICE))
    assert small.status_code == 202
    wait_for(service, small.json()["id"], headers=as_user(ALICE))


@pytest.mark.parametrize("service", [{"quota_queued_jobs": 1}], indirect=True)
def test_a_job_past_the_queued_quota_is_refused_with_retry_after(service, scenes_dir):
    scene = upload(service, ALICE, scenes_dir / "teapot.glb").json()["id"]
    slow = {"scene_id": scene, "settings": {"width": 256, "height": 256, "samples_per_pixel": 4096}}
    first = service.post("/api/jobs", json=slow, headers=as_user(ALICE)).json()["id"]
    refused = service.post("/api/jobs", json=slow, headers=as_user(ALICE))
    assert refused.status_code == 429 and int(refused.headers["retry-after"]) > 0
    assert "RT_QUOTA_QUEUED_JOBS=1" in refused.json()["detail"] and "1 jobs queued" in refused.json()["detail"]
    assert service.get("/api/me", headers=as_user(ALICE)).json()["queued_jobs"] == 1
    bob_scene = upload(service, BOB, scenes_dir / "teapot.glb").json()["id"]
    bobs = service.post("/api/jobs", json={"scene_id": bob_scene, "settings": {"width": 8, "height": 8}},
                        headers=as_user(BOB))
    assert bobs.status_code == 202, "Alice's queue is hers"
    assert service.delete(f"/api/jobs/{first}", headers=as_user(ALICE)).json()["state"] == "CANCELLED"
    again = service.post("/api/jobs", json={**slow, "settings": {"width": 8, "height": 8}}, headers=as_user(ALICE))
    assert again.status_code == 202
    wait_for(service, again.json()["id"], headers=as_user(ALICE))
