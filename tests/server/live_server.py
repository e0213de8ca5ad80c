"""A real `python -m app` for the tests that need one: raw sockets, other clients."""

import os
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "build" / "scenes"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def live_server(tmp_path_factory):
    """`python -m app` on 127.0.0.1, as make run starts it, with three small
    sample scenes; its port."""
    data = tmp_path_factory.mktemp("local")
    samples = data / "samples"
    samples.mkdir()
    for name in ("cornell.obj", "cornell.mtl", "cornell.rt.json", "teapot.glb", "smooth_sphere.glb"):
        shutil.copy(SCENES / name, samples / name)
    port = free_port()
    env = {**os.environ, "PYTHONPATH": str(ROOT / "server"), "HOST": "127.0.0.1", "PORT": str(port),
           "RT_DATA_DIR": str(data), "RT_WEB_DIR": str(data / "no-viewer"), "RT_THREADS": "1", "RT_SAMPLES_DIR": str(samples)}
    process = subprocess.Popen([sys.executable, "-m", "app"], env=env, cwd=ROOT, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
    try:
        for _ in range(300):
            if b" 200 " in raw(port, "GET /api/health HTTP/1.1", f"Host: 127.0.0.1:{port}").split(b"\r\n")[0] + b" ":
                break
            time.sleep(0.1)
        yield port
    finally:
        process.terminate()
        process.wait(10)


def raw(port: int, request_line: str, *headers: str, body: bytes = b"") -> bytes:
    """One request as bytes on a socket, exactly as given; the whole answer (or b"" before the server is up).
    A WebSocket handshake's answer is its first chunk: an accepted one stays open."""
    upgrade = any(h.lower().startswith("upgrade:") for h in headers)
    ending = [] if upgrade else [f"Content-Length: {len(body)}", "Connection: close"]
    message = "\r\n".join([request_line, *headers, *ending, "", ""])
    try:
        with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
            s.sendall(message.encode() + body)
            chunks = []
            while chunk := s.recv(65536):
                chunks.append(chunk)
                if upgrade:
                    break
            return b"".join(chunks)
    except OSError:
        return b""
