#!/usr/bin/env python3
"""Load time of the full dragon, plain GLB against Draco-compressed GLB.

The Draco files are made once by gltf-pipeline -d (renderer/samples/compressed.py):
its defaults (11-bit positions, 8-bit normals), and with 14-bit positions, into
--out, and kept while they are newer than the dragon. 11 bits merge vertices of
the dragon's smallest triangles, which the loader then drops as degenerate: the
triangle counts printed show how many. Each run loads a file with rtcore.Scene.load (read,
check, decode, finalise, BVH: what the service does for an upload) in a fresh
process, so that no run inherits another's allocator state or page cache
warmth beyond the file's own; the files alternate, --runs of each. Printed:
the sizes, every time, and the medians.

  tests/bench/compressed_load_bench.py --scenes build/scenes --out build/bench [--runs 5]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "renderer" / "samples"))
from compressed import draco_compress  # noqa: E402

TIME_ONE_LOAD = """
import sys, time
import rtcore
start = time.perf_counter()
scene = rtcore.Scene.load(sys.argv[1])
print(time.perf_counter() - start, scene.triangle_count)
"""


def load_seconds(path: Path) -> tuple[float, int]:
    result = subprocess.run([sys.executable, "-c", TIME_ONE_LOAD, str(path)], capture_output=True, text=True,
                            check=True)
    seconds, triangles = result.stdout.split()
    return float(seconds), int(triangles)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=Path, required=True, help="the sample scenes (dragon_1.glb)")
    parser.add_argument("--out", type=Path, required=True, help="where the Draco dragon is kept")
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    plain = args.scenes / "dragon_1.glb"
    draco = args.out / "dragon_1_draco.glb"
    draco14 = args.out / "dragon_1_draco14.glb"
    args.out.mkdir(parents=True, exist_ok=True)
    for path, bits in ((draco, 11), (draco14, 14)):
        if not path.exists() or path.stat().st_mtime < plain.stat().st_mtime:
            print(f"compressing {plain} with gltf-pipeline -d, {bits}-bit positions", flush=True)
            draco_compress(plain, path, bits)

    times: dict[Path, list[float]] = {plain: [], draco: [], draco14: []}
    triangles = {}
    for path in times:
        load_seconds(path)  # the page cache holds every file for every timed run
    for _ in range(args.runs):
        for path in times:
            seconds, triangles[path] = load_seconds(path)
            times[path].append(seconds)
    for path, runs in times.items():
        print(f"{path.name:<22} {path.stat().st_size / 1e6:6.2f} MB  {triangles[path]:,} triangles  "
              f"median {statistics.median(runs) * 1e3:7.1f} ms  runs " + " ".join(f"{t * 1e3:.0f}" for t in runs))
    for path in (draco, draco14):
        ratio = statistics.median(times[path]) / statistics.median(times[plain])
        print(f"{path.name} over plain: {ratio:.2f}x the load time, "
              f"{path.stat().st_size / plain.stat().st_size:.3f}x the bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
