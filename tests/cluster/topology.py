"""The docker-compose topology as processes on loopback: a Dask scheduler,
workers and the server pointed at the scheduler; the workers either share the
server's data folder or run as another user in a folder of their own, with no
access to it."""

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx
import numpy as np
import rtcore
from rt import render_pb2
from waiting import wait_until

ROOT = Path(__file__).resolve().parents[2]
VENV_BIN = Path(sys.executable).parent


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Topology:
    """The processes, started by start() and ended by stop(). With
    `shared_folder` False each worker runs in a mount namespace of its own with
    an empty tmpfs over the server's data folder, as on a machine that mounts
    a volume of its own at the same path, and in a folder of its own as its
    working directory and home."""

    def __init__(self, data_dir: Path, logs: Path, shared_folder: bool = True, workers: int = 2):
        self.scheduler_port = free_port()
        self.port = free_port()
        self.data_dir = data_dir
        self.env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "server"), str(ROOT / "build/renderer/python")]),
                    "RT_DATA_DIR": str(data_dir), "RT_SCHEDULER": f"tcp://127.0.0.1:{self.scheduler_port}",
                    "HOST": "127.0.0.1", "PORT": str(self.port), "RT_WEB_DIR": str(data_dir / "no-viewer")}
        self.logs = logs
        self.shared_folder = shared_folder
        self.worker_count = workers
        self.worker_home: Path | None = None
        self.workers: list[subprocess.Popen] = []
        self.processes: list[subprocess.Popen] = []

    def spawn(self, name: str, *args: str, env: dict | None = None, cwd: Path = ROOT) -> subprocess.Popen:
        log = open(self.logs / f"{name}.log", "ab")
        process = subprocess.Popen(args, env=env or self.env, stdout=log, stderr=subprocess.STDOUT, cwd=cwd,
                                   start_new_session=True)
        self.processes.append(process)
        return process

    def spawn_worker(self, i: int) -> subprocess.Popen:
        """Worker `i`, or a new one in its place (its log goes on in the same file)."""
        command = [str(VENV_BIN / "dask"), "worker", self.env["RT_SCHEDULER"], "--nthreads", "1", "--no-nanny",
                   "--name", f"w{i}-{time.monotonic_ns()}", "--dashboard-address", ":0"]
        if self.shared_folder:
            return self.spawn(f"worker{i}", *command)
        home = self.worker_home
        env = {**self.env, "HOME": str(home), "TMPDIR": str(home)}
        own_data_folder = ["unshare", "--mount", "--propagation", "private", "sh", "-c",
                           'mount -t tmpfs rt-worker-data "$0" && exec "$@"', str(self.data_dir)]
        return self.spawn(f"worker{i}", *own_data_folder, *command, "--local-directory", str(home), env=env, cwd=home)

    def start(self, client: httpx.Client) -> None:
        if not self.shared_folder:
            self.worker_home = Path(tempfile.mkdtemp(prefix="rt-worker-"))
        self.scheduler = self.spawn_scheduler()
        self.workers = [self.spawn_worker(i) for i in range(self.worker_count)]
        self.spawn("server", sys.executable, "-m", "app")
        wait_until(lambda: client.get("/api/health").json()["workers"] == self.worker_count, 60,
                   "the server and its workers")

    def spawn_scheduler(self) -> subprocess.Popen:
        return self.spawn("scheduler", str(VENV_BIN / "dask"), "scheduler", "--host", "127.0.0.1",
                          "--port", str(self.scheduler_port), "--dashboard-address", ":0", "--no-show")

    def stop(self) -> None:
        for process in self.processes:
            if process.poll() is None:
                os.killpg(process.pid, signal.SIGTERM)
        for process in self.processes:
            try:
                process.wait(10)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
        if self.worker_home is not None:
            shutil.rmtree(self.worker_home, ignore_errors=True)


def started(tmp_path_factory, shared_folder: bool, workers: int = 2):
    """A started topology and a client of its server, stopped when the generator ends."""
    topology = Topology(tmp_path_factory.mktemp("data"), tmp_path_factory.mktemp("logs"), shared_folder, workers)
    client = httpx.Client(base_url=f"http://127.0.0.1:{topology.port}", timeout=30)
    try:
        topology.start(client)
        yield topology, client
    finally:
        topology.stop()
        client.close()


def expected_png(scene_path: Path, camera: dict, settings: render_pb2.RenderSettings) -> np.ndarray:
    """The same render in this process, encoded as the service encodes."""
    from google.protobuf.json_format import ParseDict

    scene = rtcore.Scene.load(str(scene_path))
    camera_bytes = ParseDict(camera, render_pb2.Camera()).SerializeToString()
    return rtcore.encode_srgb8(scene.render(camera_bytes, settings.SerializeToString(), threads=2))
