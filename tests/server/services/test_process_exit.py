"""A server that rendered stops quietly: the scenes its worker keeps
(scene_cache) and its runs' stop sources (tile_tasks) are dropped as the
interpreter exits, before rtcore's teardown, where nanobind would report them
as leaked ("likely caused by a reference counting issue in the binding
code") each time a server or worker stops."""
import os
import signal
import subprocess
import sys
from pathlib import Path

import httpx
from live_server import free_port
from waiting import wait_until

ROOT = Path(__file__).resolve().parents[3]
SCENE = ROOT / "build" / "scenes" / "smooth_sphere.glb"


def test_a_server_stopped_after_a_job_reports_no_leaks(tmp_path):
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "server"), "HOST": "127.0.0.1", "PORT": str(port),
           "RT_DATA_DIR": str(tmp_path / "data"), "RT_WEB_DIR": str(tmp_path / "no-viewer"), "RT_THREADS": "1"}
    server = subprocess.Popen([sys.executable, "-m", "app"], env=env, cwd=ROOT, stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True)
    try:
        wait_until(lambda: httpx.get(f"{base}/api/health").json()["workers"], 60, "the server's worker")
        with open(SCENE, "rb") as f:
            scene = httpx.post(f"{base}/api/scenes", files={"file": (SCENE.name, f)}, timeout=60).json()
        job = httpx.post(f"{base}/api/jobs", json={"scene_id": scene["id"], "settings": {"width": 32, "height": 32}})
        job_id = job.json()["id"]
        wait_until(lambda: httpx.get(f"{base}/api/jobs/{job_id}").json()["state"] == "DONE", 60, "the job")
    finally:
        server.send_signal(signal.SIGINT)  # as Ctrl-C stops make run
        _, stderr = server.communicate(timeout=60)
    assert server.returncode == 0, stderr
    assert "Application shutdown complete" in stderr
    assert "leaked" not in stderr, stderr
