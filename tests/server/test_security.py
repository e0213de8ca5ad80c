"""RT_API_TOKEN: every /api route and the tile WebSocket need the token."""

import pytest
from fastapi.testclient import TestClient
from starlette.websockets import WebSocketDisconnect

from app.main import create_app
from service import service_settings

TOKEN = "s3cret-token"


@pytest.fixture(scope="module")
def guarded(tmp_path_factory):
    with TestClient(create_app(service_settings(tmp_path_factory.mktemp("data"), api_token=TOKEN))) as client:
        yield client


@pytest.mark.parametrize("method, url", [
    ("get", "/api/health"), ("get", "/api/scenes"), ("post", "/api/scenes"), ("get", "/api/jobs"),
    ("post", "/api/jobs"), ("get", "/api/jobs/x/image.png"), ("delete", "/api/scenes/x"),
])
def test_routes_refuse_requests_without_the_token(guarded, method, url):
    response = getattr(guarded, method)(url)
    assert response.status_code == 401 and "token" in response.json()["detail"]
    assert response.headers["www-authenticate"] == "Bearer"
    wrong = getattr(guarded, method)(url, headers={"Authorization": "Bearer nope"})
    assert wrong.status_code == 401


def test_the_token_opens_every_route(guarded, scenes_dir):
    headers = {"Authorization": f"Bearer {TOKEN}"}
    assert guarded.get("/api/health", headers=headers).status_code == 200
    with open(scenes_dir / "teapot.glb", "rb") as f:
        scene = guarded.post("/api/scenes", files={"file": ("teapot.glb", f)}, headers=headers)
    assert scene.status_code == 201
    job = guarded.post("/api/jobs", json={"scene_id": scene.json()["id"], "settings": {"width": 8, "height": 8}},
                       headers=headers).json()
    # Browsers cannot set headers on a WebSocket or a link: ?token= works too.
    assert guarded.get(f"/api/jobs/{job['id']}?token={TOKEN}").status_code == 200
    with guarded.websocket_connect(f"/api/jobs/{job['id']}/tiles?token={TOKEN}") as ws:
        assert ws.receive_bytes()


def test_the_websocket_refuses_without_the_token(guarded):
    with guarded.websocket_connect("/api/jobs/any/tiles") as ws:
        with pytest.raises(WebSocketDisconnect) as closed:
            ws.receive_bytes()
    assert closed.value.code == 4401


def test_the_viewer_and_docs_need_no_token(guarded):
    assert guarded.get("/openapi.json").status_code == 200


def test_uploads_over_the_limit_are_refused_before_they_are_read(tmp_path):
    settings = service_settings(tmp_path, max_upload_bytes=1000)
    with TestClient(create_app(settings)) as client:
        response = client.post("/api/scenes", files={"file": ("big.obj", b"v 0 0 0\n" * 400_000)})
        assert response.status_code == 413 and "over this server's limit of 1000 bytes" in response.json()["detail"]
        small_but_over = client.post("/api/scenes", files={"file": ("s.obj", b"v 0 0 0\n" * 200)})
        assert small_but_over.status_code == 413, "the streamed count catches what the header check lets by"
        assert client.get("/api/scenes").json()["scenes"] == []
        assert not any((settings.scenes_dir).iterdir()), "nothing is left on disk"


def test_a_token_in_the_query_stays_out_of_the_access_log(tmp_path, caplog):
    import logging

    with TestClient(create_app(service_settings(tmp_path, api_token=TOKEN))):
        access = logging.getLogger("uvicorn.access")
        with caplog.at_level(logging.INFO, logger="uvicorn.access"):
            # As uvicorn logs a request: client, method, path with its query, HTTP version, status.
            access.info('%s - "%s %s HTTP/%s" %d', "127.0.0.1:5000", "GET",
                        f"/api/jobs/x/tiles?a=1&token={TOKEN}&b=2", "1.1", 200)
    line = next(r.getMessage() for r in caplog.records if r.name == "uvicorn.access")
    assert TOKEN not in line and "token=[redacted]" in line and "a=1" in line and "b=2" in line
