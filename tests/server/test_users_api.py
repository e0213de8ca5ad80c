"""Named users (RT_USERS, RT_USERS_FILE): each sees and deletes only their
own scenes and jobs (another's answers 404), the samples are shared
read-only, GET /api/me names the caller, and the retention policy keeps
each user's newest jobs."""

import shutil
import time

import pytest
from fastapi.testclient import TestClient
from starlette.websockets import WebSocketDisconnect

from app.core.users import User
from app.main import create_app
from service import service_settings
from stream_reader import wait_for

ALICE = "alice-token-0123456789"
BOB = "bob-token-0123456789ab"
SIZE = {"width": 32, "height": 24}


def as_user(token):
    return {"Authorization": f"Bearer {token}"}


@pytest.fixture(scope="module")
def users(tmp_path_factory, scenes_dir):
    data = tmp_path_factory.mktemp("data")
    samples = data / "samples"
    samples.mkdir()
    for name in ("cornell.obj", "cornell.mtl", "cornell.rt.json"):
        shutil.copy(scenes_dir / name, samples / name)
    settings = service_settings(data, users=(User("alice", ALICE), User("bob", BOB)), samples_dir=samples,
                                keep_jobs=2)
    with TestClient(create_app(settings)) as client:
        yield client


@pytest.fixture(scope="module")
def sample(users):
    (scene,) = [s for s in users.get("/api/scenes", headers=as_user(ALICE)).json()["scenes"] if not s["owner"]]
    assert scene["name"] == "cornell.obj"
    return scene["id"]


@pytest.fixture(scope="module")
def alices(users, scenes_dir):
    """Alice's own scene and a done job on it."""
    with open(scenes_dir / "teapot.glb", "rb") as f:
        scene = users.post("/api/scenes", files={"file": ("teapot.glb", f)}, headers=as_user(ALICE)).json()
    assert scene["owner"] == "alice"
    job = users.post("/api/jobs", json={"scene_id": scene["id"], "settings": SIZE}, headers=as_user(ALICE)).json()
    assert job["owner"] == "alice"
    assert wait_for(users, job["id"], headers=as_user(ALICE))["state"] == "DONE"
    users.put(f"/api/jobs/{job['id']}/pin", headers=as_user(ALICE))  # outlives the retention tests below
    return scene["id"], job["id"]


def test_a_request_without_a_users_token_is_refused(users):
    for headers in ({}, as_user("not-anyones-token-at-all")):
        answer = users.get("/api/me", headers=headers)
        assert answer.status_code == 401 and "token" in answer.json()["detail"]


def test_me_names_the_user(users):
    me = users.get("/api/me", headers=as_user(BOB)).json()
    assert me["name"] == "bob" and me["keep_jobs"] == 2 and me["scenes"] == 0


def test_another_users_scene_and_job_are_missing_everywhere(users, alices):
    scene, job = alices
    bob = as_user(BOB)
    for method, url in [
        ("get", f"/api/scenes/{scene}"), ("delete", f"/api/scenes/{scene}"), ("get", f"/api/scenes/{scene}/model.glb"),
        ("get", f"/api/scenes/{scene}/bvh"), ("get", f"/api/jobs/{job}"), ("delete", f"/api/jobs/{job}"),
        ("put", f"/api/jobs/{job}/pin"), ("get", f"/api/jobs/{job}/image.png"), ("get", f"/api/jobs/{job}/image.exr"),
        ("get", f"/api/jobs/{job}/layers/color"), ("get", f"/api/jobs/{job}/accuracy"),
        ("get", f"/api/jobs/{job}/compare/{job}"), ("get", f"/api/jobs/{job}/compare/{job}/flip"),
        ("put", f"/api/scenes/{scene}/references/{job}"),
    ]:
        answer = getattr(users, method)(url, headers=bob)
        assert answer.status_code == 404, (method, url, answer.status_code)
    debug = users.post(f"/api/scenes/{scene}/debug-ray", json={"pixel": [1, 1]}, headers=bob)
    assert debug.status_code == 404
    submit = users.post("/api/jobs", json={"scene_id": scene, "settings": SIZE}, headers=bob)
    assert submit.status_code == 404 and "scene_id" in submit.json()["detail"]
    with users.websocket_connect(f"/api/jobs/{job}/tiles?token={BOB}") as ws:
        with pytest.raises(WebSocketDisconnect) as closed:
            ws.receive_bytes()
    assert closed.value.code == 4404
    # Alice still has it all.
    assert users.get(f"/api/jobs/{job}/image.png", headers=as_user(ALICE)).status_code == 200


def test_lists_hold_the_callers_own_and_the_samples(users, alices, sample):
    scene, job = alices
    alice_scenes = {s["id"] for s in users.get("/api/scenes", headers=as_user(ALICE)).json()["scenes"]}
    bob_scenes = {s["id"] for s in users.get("/api/scenes", headers=as_user(BOB)).json()["scenes"]}
    assert {scene, sample} <= alice_scenes and bob_scenes == {sample}
    assert job in {j["id"] for j in users.get("/api/jobs", headers=as_user(ALICE)).json()["jobs"]}
    assert job not in {j["id"] for j in users.get("/api/jobs", headers=as_user(BOB)).json()["jobs"]}


def test_a_sample_is_shared_read_only_and_a_job_on_it_is_its_submitters(users, sample):
    refused = users.delete(f"/api/scenes/{sample}", headers=as_user(BOB))
    assert refused.status_code == 403 and "shared" in refused.json()["detail"]
    job = users.post("/api/jobs", json={"scene_id": sample, "settings": SIZE}, headers=as_user(BOB)).json()
    assert job["owner"] == "bob"
    assert users.get(f"/api/jobs/{job['id']}", headers=as_user(ALICE)).status_code == 404
    assert wait_for(users, job["id"], headers=as_user(BOB))["state"] == "DONE"


def test_each_user_has_their_own_reference_on_a_shared_scene(users, sample):
    refs = {}
    for name, token in (("alice", ALICE), ("bob", BOB)):
        job = users.post("/api/jobs", json={"scene_id": sample, "settings": SIZE}, headers=as_user(token)).json()
        wait_for(users, job["id"], headers=as_user(token))
        marked = users.put(f"/api/scenes/{sample}/references/{job['id']}", headers=as_user(token))
        assert marked.status_code == 200 and marked.json()["reference_jobs"] == [job["id"]], name
        refs[name] = job["id"]
    seen = users.get(f"/api/scenes/{sample}", headers=as_user(ALICE)).json()
    assert seen["reference_jobs"] == [refs["alice"]], "Bob's marking kept Alice's"
    assert users.get(f"/api/jobs/{refs['bob']}/accuracy", headers=as_user(BOB)).json()["reference_id"] == refs["bob"]
    assert users.delete(f"/api/scenes/{sample}/references/{refs['alice']}", headers=as_user(BOB)).status_code == 404
    for name, token in (("alice", ALICE), ("bob", BOB)):
        assert users.delete(f"/api/scenes/{sample}/references/{refs[name]}", headers=as_user(token)).status_code == 200


def test_retention_keeps_each_users_newest_jobs(users, sample):
    # keep_jobs=2: Bob's three jobs leave him two; Alice's (her pinned one
    # and whatever she has) are not pushed out by Bob's.
    alice_before = {j["id"] for j in users.get("/api/jobs", headers=as_user(ALICE)).json()["jobs"]}
    bob = [users.post("/api/jobs", json={"scene_id": sample, "settings": SIZE}, headers=as_user(BOB)).json()["id"]
           for _ in range(3)]
    assert wait_for(users, bob[-1], headers=as_user(BOB))["state"] == "DONE"
    deadline = time.monotonic() + 30  # the policy runs as each job ends: as the last of the three does
    while users.get(f"/api/jobs/{bob[0]}", headers=as_user(BOB)).status_code != 404:
        assert time.monotonic() < deadline, "Bob's oldest job outlived his newest two"
        time.sleep(0.05)
    listed = [j["id"] for j in users.get("/api/jobs", headers=as_user(BOB)).json()["jobs"]]
    assert listed == bob[:0:-1]
    alice_after = {j["id"] for j in users.get("/api/jobs", headers=as_user(ALICE)).json()["jobs"]}
    assert alice_before and alice_before <= alice_after


def test_without_users_the_one_local_user_is_named_local(client):
    me = client.get("/api/me").json()
    assert me["name"] == "local"


# --- settings ------------------------------------------------------------------

def test_users_come_from_the_environment_and_a_file(monkeypatch, tmp_path):
    from app.core.users import load_users
    file = tmp_path / "users"
    file.write_text("# name token\n\ncarol carol-token-0123456789\n")
    users = load_users({"RT_USERS": "alice:alice-token-0123456789, bob:bob-token-0123456789",
                        "RT_USERS_FILE": str(file)})
    assert [u.name for u in users] == ["alice", "bob", "carol"]
    assert "alice-token" not in repr(users), "settings print without tokens"


@pytest.mark.parametrize("environ, problem", [
    ({"RT_USERS": "alice:alice-token-0123456789,Alice:other-token-0123456789"}, "named again"),
    ({"RT_USERS": "alice:same-token-0123456789,bob:same-token-0123456789"}, "the same token as user 'alice'"),
    ({"RT_USERS": "alice:"}, "expected a name and a token"),
    ({"RT_USERS": "alice:short"}, "shorter than 16 characters"),
    ({"RT_USERS": "al ice:alice-token-0123456789"}, "the user name is not"),
    ({"RT_USERS_FILE": "/no/such/file"}, "cannot read it"),
    ({"RT_USERS": "Local:local-token-0123456789"}, "one user without named users"),
    ({"RT_USERS": "alice:alice-token-0123456789", "RT_API_TOKEN": "x"}, "RT_API_TOKEN"),
])
def test_a_bad_users_setting_stops_the_server_naming_it(environ, problem):
    from app.core.users import load_users
    with pytest.raises(SystemExit) as stopped:
        load_users(environ)
    assert problem in str(stopped.value)
    assert "0123456789" not in str(stopped.value), "no token is echoed"


def test_a_file_line_holding_a_token_alone_is_not_echoed(tmp_path):
    from app.core.users import load_users
    file = tmp_path / "users"
    file.write_text("alice alice-token-0123456789\nlonely-token-0123456789\n")
    with pytest.raises(SystemExit, match="line 2: expected a name and a token") as stopped:
        load_users({"RT_USERS_FILE": str(file)})
    assert "lonely" not in str(stopped.value)
