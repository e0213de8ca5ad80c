"""The docker-compose topology as processes on loopback: a Dask scheduler, two
workers and the server pointed at the scheduler. A cancelled job's tiles stop
on the workers; a worker killed mid-job costs only its tiles: the job
completes with the same image."""

import io
import subprocess
import time

import numpy as np
import pytest
import yaml
from PIL import Image
from rt import render_pb2

from topology import ROOT, expected_png, started, wait_until


@pytest.fixture(scope="module")
def service(tmp_path_factory):
    yield from started(tmp_path_factory, shared_folder=True)


def executing_tiles(topology) -> dict[str, int]:
    """Tasks each worker's threads are running, cancelled ones included."""
    from distributed import Client

    with Client(topology.env["RT_SCHEDULER"], timeout="20s") as dask_client:
        return dask_client.run(lambda dask_worker: len(dask_worker.state.executing))


def test_cancel_stops_the_tiles_running_on_the_workers(service, scenes_dir):
    topology, client = service
    with open(scenes_dir / "dragon_2.glb", "rb") as f:
        scene = client.post("/api/scenes", files={"file": ("dragon_2.glb", f)}).json()
    # Its preview alone (128 x 128 pixels at 2048 samples) keeps a worker busy for a minute.
    settings = {"width": 1024, "height": 1024, "samples_per_pixel": 2048}
    job = client.post("/api/jobs", json={"scene_id": scene["id"], "settings": settings}).json()
    wait_until(lambda: sum(executing_tiles(topology).values()) > 0, 30, "the preview tile to start")
    assert client.delete(f"/api/jobs/{job['id']}").json()["state"] == "CANCELLED"
    cancelled = time.monotonic()
    wait_until(lambda: sum(executing_tiles(topology).values()) == 0, 10, "the workers to stop the tile")
    assert time.monotonic() - cancelled < 1.5, "the workers went on rendering a cancelled job's tile"


def test_a_killed_worker_costs_only_its_tiles(service, scenes_dir):
    topology, client = service
    with open(scenes_dir / "dragon_3.glb", "rb") as f:
        scene = client.post("/api/scenes", files={"file": ("dragon_3.glb", f)}).json()
    # Heavy enough (several seconds on 2 cores) that a kill after the first
    # tile lands mid-job, with room to spare as the renderer gets faster: at
    # 4 samples, killing after the third of 6 tiles, the job sometimes ended first.
    settings = {"width": 640, "height": 480, "max_depth": 3, "light_samples": 4, "samples_per_pixel": 16}
    job = client.post("/api/jobs", json={"scene_id": scene["id"], "settings": settings}).json()
    wait_until(lambda: client.get(f"/api/jobs/{job['id']}").json()["tiles_done"] >= 1, 60, "the first tile")
    victim = topology.workers[0]
    victim.kill()
    victim.wait(10)
    at_kill = client.get(f"/api/jobs/{job['id']}").json()
    assert at_kill["tiles_done"] < at_kill["tiles_total"], "the job ended before the worker was killed"
    done = wait_until(lambda: (j := client.get(f"/api/jobs/{job['id']}").json())["state"] in
                      ("DONE", "FAILED", "CANCELLED") and j, 120, "the job to end")
    assert done["state"] == "DONE", done["error"]
    assert done["tiles_done"] == done["tiles_total"]
    # Both workers see the server's data folder and wrote their tiles there.
    assert 0 < done["tiles_via_shared_folder"] <= done["tiles_total"] and done["tiles_via_network"] == 0
    assert client.get("/api/health").json()["workers"] == 1
    png = np.asarray(Image.open(io.BytesIO(client.get(f"/api/jobs/{job['id']}/image.png").content)).convert("RGBA"))
    reference = expected_png(scenes_dir / "dragon_3.glb", done["request"]["camera"],
                             render_pb2.RenderSettings(width=640, height=480, max_depth=3, light_samples=4,
                                                       samples_per_pixel=16))
    assert np.array_equal(png, reference)


def test_each_worker_renders_on_as_many_threads_as_it_has(service):
    """The server's RenderWorkerSetup plugin reached the worker processes: a
    `dask worker --nthreads 1` renders its tiles on one thread, not on all cores."""
    from distributed import Client

    topology, _ = service
    with Client(topology.env["RT_SCHEDULER"], timeout="20s") as dask_client:
        threads = dask_client.run(lambda: __import__("rtcore").render_threads())
    assert threads and set(threads.values()) == {1}, threads


def test_the_compose_file_describes_the_same_topology():
    compose = yaml.safe_load((ROOT / "docker-compose.yml").read_text())
    services = compose["services"]
    assert set(services) == {"server", "scheduler", "worker"}
    assert services["worker"]["deploy"]["replicas"] == 2
    assert services["server"]["environment"]["RT_SCHEDULER"] == "tcp://scheduler:8786"
    assert "dask" in services["scheduler"]["command"] and "scheduler" in services["scheduler"]["command"]
    for name in services:
        assert any(v.startswith("rt-data:") for v in services[name]["volumes"]), name
    dockerfile = (ROOT / "Dockerfile").read_text()
    assert dockerfile.count("FROM ") >= 2, "a multi-stage build"
    docker = subprocess.run(["docker", "compose", "config", "-q"], cwd=ROOT, capture_output=True, text=True) \
        if _has_docker_compose() else None
    if docker is not None:
        assert docker.returncode == 0, docker.stderr


def _has_docker_compose() -> bool:
    try:
        return subprocess.run(["docker", "compose", "version"], capture_output=True).returncode == 0
    except OSError:
        return False
