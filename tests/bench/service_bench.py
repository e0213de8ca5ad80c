#!/usr/bin/env python3
"""The job service against rtrender on the same machine, in one run.

A server with its embedded Dask cluster is started as `make run` starts it; the
full dragon is uploaded (so it is loaded), then each round
- rtrender renders it --batch times, each a process of its own (the mean of
  its render times, without loading and writing: the issue's figure; and,
  beside it, render and write, as the service's time includes saving its
  layers); as many images as the service's batch, so that a burst of load
  from elsewhere on the machine is as likely to fall on either side;
- the service renders the same image (same camera and settings) alone, while a
  WebSocket client watches: the time from POST /api/jobs to the first tile and
  to the stream's end (one job's latency);
- the service renders it --batch times, all posted at once, nobody watching:
  from the first POST to the last job's finished_at (the server's clock, the
  same machine's), per image. This is the service's throughput, the issue's
  figure: a batch client does not download every tile;
- the same batch with every job watched on its WebSocket by a client on the
  same cores (viewers are usually elsewhere; here each costs the service's
  cores what it takes to receive 4 MB of tiles per image).
Printed: the medians, and the throughput of the service over rtrender's.

  tests/bench/service_bench.py --scenes build/scenes --rtrender build/rtrender [--size 1024] [--rounds 9]
"""

from __future__ import annotations

import argparse
import json
import os
import re
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import httpx
from rt import job_pb2
from websockets.sync.client import connect

ROOT = Path(__file__).resolve().parents[2]
RENDER_MS = re.compile(r"render ([\d.]+) ms")
WRITE_MS = re.compile(r"write ([\d.]+) ms")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_server(data_dir: Path, port: int, **env_vars: str) -> subprocess.Popen:
    """`python -m app` as make run starts it (with `env_vars` besides), once its cluster has a worker."""
    env = {**os.environ, "RT_DATA_DIR": str(data_dir), "PORT": str(port), "HOST": "127.0.0.1",
           "PYTHONPATH": str(ROOT / "server"), **env_vars}
    server = subprocess.Popen([sys.executable, "-m", "app"], env=env, cwd=ROOT, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        try:
            if httpx.get(f"http://127.0.0.1:{port}/api/health").json()["workers"]:
                return server
        except httpx.HTTPError:
            time.sleep(0.2)
    server.kill()
    sys.exit("service_bench: the server did not start")


def rtrender_ms(rtrender: Path, scene: Path, camera: dict, settings: dict, out: Path) -> tuple[float, float]:
    """rtrender's render time, and the time it then takes to write its PNG."""
    camera_file = out / "camera.json"
    settings_file = out / "settings.json"
    camera_file.write_text(json.dumps(camera))
    settings_file.write_text(json.dumps(settings))
    result = subprocess.run([str(rtrender), str(scene), "-o", str(out / "rtrender.png"), "--quiet",
                             "--camera-file", str(camera_file), "--settings", str(settings_file)],
                            capture_output=True, text=True, check=True)
    output = result.stdout + result.stderr
    return float(RENDER_MS.search(output).group(1)), float(WRITE_MS.search(output).group(1))


def service_run(base: str, scene_id: str, camera: dict, settings: dict) -> tuple[float, float]:
    """(seconds from POST to the first tile, seconds from POST to the end)."""
    posted = time.perf_counter()
    job = httpx.post(f"{base}/api/jobs", json={"scene_id": scene_id, "camera": camera, "settings": settings}).json()
    return watch(base, job["id"], posted)


def batch_run(base: str, scene_id: str, camera: dict, settings: dict, count: int) -> float:
    """Seconds from the first of `count` POSTs to the end of the last job's stream."""
    posted = time.perf_counter()
    body = {"scene_id": scene_id, "camera": camera, "settings": settings}
    ids = [httpx.post(f"{base}/api/jobs", json=body).json()["id"] for _ in range(count)]
    with ThreadPoolExecutor(count) as pool:
        list(pool.map(lambda job_id: watch(base, job_id, posted), ids))
    return time.perf_counter() - posted


def batch_unwatched(base: str, scene_id: str, camera: dict, settings: dict, count: int) -> float:
    """Seconds from the first of `count` POSTs to the last job's finished_at,
    checking on the jobs every 0.25 s, as a batch client would: one request
    for the newest `count` jobs (nobody else posts any)."""
    body = {"scene_id": scene_id, "camera": camera, "settings": settings}
    with httpx.Client(base_url=base, timeout=60) as http:
        posted = time.time()
        ids = [http.post("/api/jobs", json=body).json()["id"] for _ in range(count)]
        while True:
            jobs = http.get("/api/jobs", params={"limit": count}).json()["jobs"]
            if sorted(job["id"] for job in jobs) != sorted(ids):
                sys.exit("service_bench: someone else posted jobs to the benchmark's server")
            if all(job["state"] in ("DONE", "FAILED", "CANCELLED") for job in jobs):
                break
            time.sleep(0.25)
    if any(job["state"] != "DONE" for job in jobs):
        sys.exit(f"service_bench: a job ended {[job['state'] for job in jobs]}")
    return max(job["finished_at"] for job in jobs) - posted


def watch(base: str, job_id: str, posted: float) -> tuple[float, float]:
    """Follows a job's tile stream to its end: (seconds from `posted` to the
    first tile, to the end). Exits when the job did not end DONE."""
    ws_base = base.replace("http://", "ws://")
    first = None
    with connect(f"{ws_base}/api/jobs/{job_id}/tiles", max_size=None) as ws:
        for message in ws:
            kind = job_pb2.TileStreamMessage.FromString(message).WhichOneof("message")
            if kind == "tile" and first is None:
                first = time.perf_counter() - posted
            if kind == "end":
                break
    ended = time.perf_counter() - posted
    state = httpx.get(f"{base}/api/jobs/{job_id}").json()["state"]
    if state != "DONE":
        sys.exit(f"service_bench: the job ended {state}")
    return first, ended


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=Path, required=True)
    parser.add_argument("--rtrender", type=Path, required=True)
    parser.add_argument("--scene", default="dragon_1.glb")
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--rounds", type=int, default=9,
                        help="rounds of rtrender then the service; more make the medians steadier on a noisy machine")
    parser.add_argument("--batch", type=int, default=4, help="jobs posted at once for the throughput figure")
    args = parser.parse_args()

    settings = {"width": args.size, "height": args.size}
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    with tempfile.TemporaryDirectory() as tmp:
        server = start_server(Path(tmp) / "data", port)
        try:
            with open(args.scenes / args.scene, "rb") as f:
                scene = httpx.post(f"{base}/api/scenes", files={"file": (args.scene, f)}, timeout=300).json()
            camera = scene["default_camera"]
            service_run(base, scene["id"], camera, {"width": 64, "height": 64})  # warm up the worker threads
            ours, theirs, writes, firsts, batched, watched = [], [], [], [], [], []
            for _ in range(args.rounds):
                # As many images as the batch: both sides spend as long exposed to whatever else the machine runs.
                runs = [rtrender_ms(args.rtrender, args.scenes / args.scene, camera, settings, Path(tmp))
                        for _ in range(args.batch)]
                theirs.append(statistics.mean(render for render, _ in runs))
                writes.append(statistics.mean(render + write for render, write in runs))
                first, total = service_run(base, scene["id"], camera, settings)
                ours.append(total * 1000)
                firsts.append(first * 1000)
                batched.append(batch_unwatched(base, scene["id"], camera, settings, args.batch) * 1000 / args.batch)
                watched.append(batch_run(base, scene["id"], camera, settings, args.batch) * 1000 / args.batch)
        finally:
            server.terminate()
            server.wait(30)

    print(f"\nService against rtrender: {args.scene}, {args.size}x{args.size}, default settings, "
          f"{os.cpu_count()} cores, embedded cluster, {args.rounds} rounds (median)")
    print(f"  rtrender render, per image           {statistics.median(theirs):9.1f} ms   rounds: "
          + ", ".join(f"{t:.0f}" for t in theirs))
    print(f"  service, one job alone, POST to end  {statistics.median(ours):9.1f} ms   rounds: "
          + ", ".join(f"{t:.0f}" for t in ours))
    print(f"  {f'service, {args.batch} jobs at once, per image':37s}{statistics.median(batched):9.1f} ms   rounds: "
          + ", ".join(f"{t:.0f}" for t in batched))
    print(f"  {'the same, each watched on WebSocket':37s}{statistics.median(watched):9.1f} ms   rounds: "
          + ", ".join(f"{t:.0f}" for t in watched))
    ratio = statistics.median(t / b for t, b in zip(theirs, batched))
    viewed = statistics.median(t / w for t, w in zip(theirs, watched))
    alone = statistics.median(t / o for t, o in zip(theirs, ours))
    print(f"  throughput service / rtrender: {ratio:.2f}   (target >= 0.95; every job watched by a client on the "
          f"same cores: {viewed:.2f}; a job alone, watched: {alone:.2f})")
    written = statistics.median(t / b for t, b in zip(writes, batched))
    print(f"  rtrender render and write its PNG    {statistics.median(writes):9.1f} ms   (image files out per second, "
          f"as the service's are: throughput against it {written:.2f})")
    print(f"  first tile after POST                {statistics.median(firsts):9.1f} ms   (target <= 500 ms)   rounds: "
          + ", ".join(f"{t:.0f}" for t in firsts))
    return 0


if __name__ == "__main__":
    sys.exit(main())
