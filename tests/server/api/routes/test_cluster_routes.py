"""api/routes/cluster.py and services/scene_fetch.py: a worker that does not
see the data folder fetches a scene's files by content hash, with the cluster
secret and nothing else; it loads the same scene the server stores."""

import pytest
import rtcore
from fastapi.testclient import TestClient
from rt import job_pb2

from app.services import scene_fetch
from app.services.data_access import DataAccess


@pytest.fixture
def stored(client, cornell_id):
    return client.app.state.scenes.get(cornell_id)


def worker_headers(client) -> dict[str, str]:
    return {"Authorization": f"Bearer {client.app.state.data_access.secret}"}


def test_the_listing_names_every_file_and_the_one_to_load(client, stored):
    answer = client.get(f"/cluster/scenes/{stored.sha256}", headers=worker_headers(client))
    assert answer.status_code == 200 and answer.headers["content-type"] == "application/x-protobuf"
    listing = job_pb2.SceneFiles.FromString(answer.content)
    assert listing.scene_file == "cornell.obj"
    assert {f.path for f in listing.files} == {"cornell.obj", "cornell.mtl", "cornell.rt.json"}
    for f in listing.files:
        body = client.get(f"/cluster/scenes/{stored.sha256}/files/{f.path}", headers=worker_headers(client))
        assert body.status_code == 200 and len(body.content) == f.size
        assert body.content == (stored.scene_file.parent / f.path).read_bytes()


@pytest.mark.parametrize("headers", [{}, {"Authorization": "Bearer not-the-secret"}])
def test_only_the_cluster_secret_opens_it(client, stored, headers):
    for path in (f"/cluster/scenes/{stored.sha256}", f"/cluster/scenes/{stored.sha256}/files/cornell.obj"):
        answer = client.get(path, headers=headers)
        assert answer.status_code == 401 and "render workers" in answer.json()["detail"]


def test_the_user_token_is_not_the_cluster_secret(client, stored, monkeypatch):
    assert client.get(f"/cluster/scenes/{stored.sha256}", params={"token": ""}).status_code == 401


@pytest.mark.parametrize("path", ["../stored.json", "..%2Fstored.json", "%2E%2E/scene.json", "/etc/passwd",
                                  "no-such-file.obj", "."])
def test_no_path_leaves_the_scenes_files(client, stored, path):
    answer = client.get(f"/cluster/scenes/{stored.sha256}/files/{path}", headers=worker_headers(client))
    assert answer.status_code == 404, answer.text


def test_an_unknown_hash_is_404(client):
    answer = client.get("/cluster/scenes/" + "0" * 64, headers=worker_headers(client))
    assert answer.status_code == 404 and "0" * 64 in answer.json()["detail"]


def test_the_cluster_routes_stay_out_of_the_public_schema(client):
    assert not any(p.startswith("/cluster") for p in client.get("/openapi.json").json()["paths"])


class AppClient(TestClient):
    """The test's app answering without a socket, its lifespan (a second
    service) not started by `with`."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def served_by(client, monkeypatch) -> DataAccess:
    """Workers' requests answered by the test's app instead of a socket."""
    app = client.app
    monkeypatch.setattr(scene_fetch.httpx, "Client", lambda headers, timeout: AppClient(app, headers=headers))
    return DataAccess("/nowhere", "other-folder", "http://testserver", app.state.data_access.secret)


def test_a_fetched_scene_is_the_stored_scene(client, stored, monkeypatch):
    scene = scene_fetch.fetch_scene(served_by(client, monkeypatch), stored.sha256)
    here = rtcore.Scene.load(str(stored.scene_file))
    assert job_pb2.SceneInfo.FromString(scene.info) == job_pb2.SceneInfo.FromString(here.info)
    assert scene.memory_bytes == here.memory_bytes


def test_a_fetch_that_fails_names_the_server_and_the_status(client, monkeypatch):
    access = served_by(client, monkeypatch)
    with pytest.raises(scene_fetch.SceneFetchError, match=r"http://testserver: HTTP 404"):
        scene_fetch.fetch_scene(access, "f" * 64)
    with pytest.raises(scene_fetch.SceneFetchError, match="HTTP 401"):
        scene_fetch.fetch_scene(DataAccess("/nowhere", "x", "http://testserver", "wrong"), "f" * 64)


@pytest.mark.parametrize("path", ["../x.obj", "/etc/passwd", "a/../../x", "a\\..\\x", ""])
def test_a_listing_naming_a_path_outside_the_folder_is_refused(path):
    with pytest.raises(scene_fetch.SceneFetchError, match="outside the scene's folder"):
        scene_fetch._relative(path)
