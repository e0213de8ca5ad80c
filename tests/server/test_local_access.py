"""A local server that web pages cannot drive (core/local_access.py): the
raw requests a hostile page makes a browser send, against a real server bound
to 127.0.0.1 as `make run` binds it, and the settings that open it up."""

import io
import zipfile

import pytest
from fastapi.testclient import TestClient
from starlette.websockets import WebSocketDisconnect

from app.main import create_app
from live_server import raw
from service import service_settings


def status(answer: bytes) -> int:
    return int(answer.split(b" ", 2)[1])


def upload_body() -> tuple[str, bytes]:
    boundary = "rtboundary"
    scene = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
    body = (f"--{boundary}\r\nContent-Disposition: form-data; name=\"file\"; filename=\"tri.obj\"\r\n"
            f"Content-Type: application/octet-stream\r\n\r\n").encode() + scene + f"\r\n--{boundary}--\r\n".encode()
    return f"Content-Type: multipart/form-data; boundary={boundary}", body


def scene_count(port: int) -> int:
    answer = raw(port, "GET /api/scenes HTTP/1.1", f"Host: 127.0.0.1:{port}")
    return answer.count(b'"id"')


def test_a_form_post_from_another_site_is_refused(live_server):
    kind, body = upload_body()
    before = scene_count(live_server)
    answer = raw(live_server, "POST /api/scenes HTTP/1.1", f"Host: 127.0.0.1:{live_server}",
                 "Origin: http://evil.example", kind, body=body)
    assert status(answer) == 403 and b"Origin 'http://evil.example'" in answer and b"RT_ALLOWED_ORIGINS" in answer
    # The same, as a browser that sends only Sec-Fetch-Site.
    answer = raw(live_server, "POST /api/scenes HTTP/1.1", f"Host: 127.0.0.1:{live_server}",
                 "Sec-Fetch-Site: cross-site", kind, body=body)
    assert status(answer) == 403 and b"cross-site" in answer
    assert scene_count(live_server) == before, "nothing was stored"
    # From the live_server's own page, or from a client that is not a browser, it is accepted.
    own = raw(live_server, "POST /api/scenes HTTP/1.1", f"Host: 127.0.0.1:{live_server}",
              f"Origin: http://127.0.0.1:{live_server}", kind, body=body)
    assert status(own) == 201, own
    curl = raw(live_server, "POST /api/scenes HTTP/1.1", f"Host: localhost:{live_server}", kind, body=body)
    assert status(curl) == 201
    assert scene_count(live_server) == before + 2


def test_a_rebound_host_name_is_refused(live_server):
    answer = raw(live_server, "GET /api/health HTTP/1.1", "Host: evil.example")
    assert status(answer) == 400 and b"Host 'evil.example'" in answer and b"RT_ALLOWED_HOSTS" in answer
    assert status(raw(live_server, "GET / HTTP/1.1", f"Host: evil.example:{live_server}")) == 400
    assert status(raw(live_server, "GET /api/scenes HTTP/1.1", "Host: 127.0.0.1.evil.example")) == 400
    for host in (f"127.0.0.1:{live_server}", f"localhost:{live_server}", f"[::1]:{live_server}", "localhost"):
        assert status(raw(live_server, "GET /api/health HTTP/1.1", f"Host: {host}")) == 200, host


def test_the_tile_stream_refuses_other_sites(live_server):
    handshake = ("GET /api/jobs/x/tiles HTTP/1.1", f"Host: 127.0.0.1:{live_server}", "Upgrade: websocket",
                 "Connection: Upgrade", "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==", "Sec-WebSocket-Version: 13")
    answer = raw(live_server, *handshake[:1], *handshake[1:], "Origin: http://evil.example")
    assert status(answer) == 403
    own = raw(live_server, *handshake[:1], *handshake[1:], f"Origin: http://127.0.0.1:{live_server}")
    assert status(own) == 101


def test_every_answer_has_the_security_headers(live_server):
    answer = raw(live_server, "GET /api/health HTTP/1.1", f"Host: 127.0.0.1:{live_server}").lower()
    for header in (b"x-content-type-options: nosniff", b"referrer-policy: no-referrer", b"x-frame-options: deny",
                   b"cross-origin-opener-policy: same-origin", b"content-security-policy: default-src 'self'"):
        assert header in answer, header
    refused = raw(live_server, "GET /api/health HTTP/1.1", "Host: evil.example").lower()
    assert b"x-frame-options: deny" in refused
    docs = raw(live_server, "GET /docs HTTP/1.1", f"Host: 127.0.0.1:{live_server}").lower()
    assert b"content-security-policy" not in docs, "Swagger UI comes from its CDN"


def test_configured_names_and_origins_are_let_in(tmp_path):
    settings = service_settings(tmp_path, allowed_hosts=("testserver", "render.example"),
                                allowed_origins=("https://app.example",))
    with TestClient(create_app(settings)) as client:
        assert client.get("/api/health", headers={"Host": "render.example"}).status_code == 200
        assert client.get("/api/health", headers={"Host": "other.example"}).status_code == 400
        bundle = io.BytesIO()
        with zipfile.ZipFile(bundle, "w") as z:
            z.writestr("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        files = {"file": ("tri.zip", bundle.getvalue())}
        assert client.post("/api/scenes", files=files, headers={"Origin": "https://app.example"}).status_code == 201
        assert client.post("/api/scenes", files=files, headers={"Origin": "https://evil.example"}).status_code == 403
        assert client.post("/api/scenes", files=files, headers={"Origin": "null"}).status_code == 403
        with pytest.raises(WebSocketDisconnect):
            with client.websocket_connect("/api/jobs/x/tiles", headers={"Origin": "https://evil.example"}) as ws:
                ws.receive_bytes()


def test_bound_to_all_interfaces_any_host_is_answered_unless_names_are_given(tmp_path):
    with TestClient(create_app(service_settings(tmp_path, host="0.0.0.0", allowed_hosts=()))) as client:
        assert client.get("/api/health", headers={"Host": "render.lan:8000"}).status_code == 200
    with TestClient(create_app(service_settings(tmp_path, host="0.0.0.0", allowed_hosts=("render.lan",)))) as client:
        assert client.get("/api/health", headers={"Host": "render.lan:8000"}).status_code == 200
        assert client.get("/api/health", headers={"Host": "evil.example"}).status_code == 400
