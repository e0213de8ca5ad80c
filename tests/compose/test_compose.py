"""`make test-compose`: the Dockerfile built and docker-compose.yml run under
podman, on a host that reaches no container registry (base images made
locally, tests/compose/base_images.py). The image's renderer runs on a CPU
without AVX; every service's health check passes; a job rendered through the
containers, and one whose worker container is killed mid-job, give the image
a local render gives. Everything is torn down, whatever fails."""

import io
import re
import subprocess
from pathlib import Path

import httpx
import numpy as np
import pytest
import rtcore
from google.protobuf.json_format import ParseDict
from PIL import Image
from rt import render_pb2

# pytest puts this folder on sys.path (it is no package).
from base_images import ensure_base_images
from compose_topology import ComposeTopology
from host_setup import prepare_host
from podman_cli import PODMAN, podman
from waiting import wait_until

ROOT = Path(__file__).resolve().parents[2]
# The name docker-compose.yml gives the image; podman finds `rt:latest` as this.
IMAGE = "localhost/rt:latest"
PROJECT = "rt-compose-test"
# OpenEXR's capDate attribute: the time of writing, the only byte that may differ.
CAP_DATE = re.compile(rb"capDate\x00string\x00.{4}\d{4}:\d\d:\d\d \d\d:\d\d:\d\d", re.S)


@pytest.fixture(scope="module")
def logs() -> Path:
    """The image build's output and each container's log, kept after the run."""
    folder = ROOT / "test-artifacts/compose"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


@pytest.fixture(scope="module")
def image(logs) -> str:
    prepare_host()
    build_args = [arg for name, value in ensure_base_images().items() for arg in ("--build-arg", f"{name}={value}")]
    with open(logs / "build.log", "w") as log:
        build = subprocess.run([*PODMAN, "build", *build_args, "-t", IMAGE, str(ROOT)],
                               stdout=log, stderr=subprocess.STDOUT, timeout=3 * 3600)
    assert build.returncode == 0, f"podman build failed: see {logs / 'build.log'}"
    return IMAGE


@pytest.fixture(scope="module")
def topology(image, logs):
    topology = ComposeTopology(ROOT / "docker-compose.yml", PROJECT, logs)
    try:
        topology.up()
        yield topology
    finally:
        topology.down()


@pytest.fixture(scope="module")
def client(topology):
    address = topology.published(topology.services["server"].containers[0], 8000)
    with httpx.Client(base_url=f"http://{address}", timeout=30) as client:
        yield client


def local_png(scene_path: Path, camera: dict, settings: dict) -> np.ndarray:
    """The job's render made in this process by the host's build, encoded as the service encodes."""
    scene = rtcore.Scene.load(str(scene_path))
    camera_bytes = ParseDict(camera, render_pb2.Camera()).SerializeToString()
    settings_bytes = ParseDict(settings, render_pb2.RenderSettings()).SerializeToString()
    return rtcore.encode_srgb8(scene.render(camera_bytes, settings_bytes, threads=2))


def job_png(client: httpx.Client, job_id: str) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(client.get(f"/api/jobs/{job_id}/image.png").content)).convert("RGBA"))


def upload(client: httpx.Client, path: Path) -> dict:
    with open(path, "rb") as f:
        response = client.post("/api/scenes", files={"file": (path.name, f)})
    assert response.status_code == 201, response.text
    return response.json()


def wait_for_end(client: httpx.Client, job_id: str, timeout: float) -> dict:
    return wait_until(lambda: (j := client.get(f"/api/jobs/{job_id}").json())["state"] in
                      ("DONE", "FAILED", "CANCELLED") and j, timeout, f"job {job_id} to end")


def test_the_images_renderer_runs_on_a_cpu_without_avx(image, scenes_dir, rtrender, tmp_path):
    """The image's own rtrender, its libraries from the image, under qemu-user's
    Nehalem model (SSE4.2, no AVX): the generic kernels, and the image the
    host's build renders with its widest kernels."""
    scene, size = scenes_dir / "bunny.glb", ("--width", "48", "--height", "36", "--quiet")
    root = podman("image", "mount", image).stdout.strip()
    try:
        old_cpu = subprocess.run(["qemu-x86_64", "-L", root, "-cpu", "Nehalem", f"{root}/usr/local/bin/rtrender",
                                  scene, "-o", tmp_path / "nehalem.exr", *size],
                                 capture_output=True, text=True, timeout=600)
    finally:
        podman("image", "unmount", image, check=False)
    assert old_cpu.returncode == 0, old_cpu.stderr
    assert "(generic kernels)" in old_cpu.stdout, old_cpu.stdout
    here = subprocess.run([rtrender, scene, "-o", tmp_path / "here.exr", *size], capture_output=True, text=True)
    assert here.returncode == 0, here.stderr
    pixels = [CAP_DATE.sub(b"", (tmp_path / name).read_bytes()) for name in ("nehalem.exr", "here.exr")]
    assert pixels[0] == pixels[1], "the image's renderer on an old CPU and the host's build disagree"


def test_every_service_passes_its_health_check(topology, client):
    """`up` waited for each check to pass; podman's record says so too."""
    for service in topology.services.values():
        assert len(service.containers) == service.replicas
        for container in service.containers:
            assert topology.health(container) == "healthy", (container, topology.log(container)[-2000:])
    assert client.get("/api/health").json()["workers"] == 2


def test_a_job_through_the_containers_matches_a_local_render(client, scenes_dir):
    # A .glb: one file holds all of it (an OBJ's .mtl and sidecar would need uploading too).
    scene = upload(client, scenes_dir / "bunny.glb")
    settings = {"width": 160, "height": 120, "samples_per_pixel": 4}
    job = client.post("/api/jobs", json={"scene_id": scene["id"], "settings": settings}).json()
    done = wait_for_end(client, job["id"], 120)
    assert done["state"] == "DONE", done.get("error")
    assert np.array_equal(job_png(client, job["id"]),
                          local_png(scenes_dir / "bunny.glb", done["request"]["camera"], settings))


def test_a_killed_worker_container_costs_only_its_tiles(topology, client, scenes_dir):
    scene = upload(client, scenes_dir / "dragon_3.glb")
    # Heavy enough (several seconds on 2 cores) that a kill after the first tile lands mid-job.
    settings = {"width": 640, "height": 480, "max_depth": 3, "light_samples": 4, "samples_per_pixel": 16}
    job = client.post("/api/jobs", json={"scene_id": scene["id"], "settings": settings}).json()
    wait_until(lambda: client.get(f"/api/jobs/{job['id']}").json()["tiles_done"] >= 1, 120, "the first tile")
    topology.kill(topology.services["worker"].containers[0])
    at_kill = client.get(f"/api/jobs/{job['id']}").json()
    assert at_kill["tiles_done"] < at_kill["tiles_total"], "the job ended before the worker was killed"
    done = wait_for_end(client, job["id"], 600)
    assert done["state"] == "DONE", done.get("error")
    assert done["tiles_done"] == done["tiles_total"]
    # The compose file sets no restart policy: the job finished on the one worker left.
    wait_until(lambda: client.get("/api/health").json()["workers"] == 1, 60, "the scheduler to drop the worker")
    assert np.array_equal(job_png(client, job["id"]),
                          local_png(scenes_dir / "dragon_3.glb", done["request"]["camera"], settings))
