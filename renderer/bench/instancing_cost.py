#!/usr/bin/env python3
"""What instancing saves: dragon_3 (48K triangles) placed 210 times, once as
one mesh that 210 nodes share (two-level: one BVH for the mesh, a top-level
tree over the instances) and once with a copy of the mesh per node (the
loader flattens those into 10 million world-space triangles). Both are
rendered by rtrender in turns.

Prints, for each: rtrender's wall time (load, build, render, write), its peak
resident memory, the BVH build and the render time, medians and ranges; and
the ratios. Issue 16's targets: the shared scene loads and builds in under
0.5 s and uses under 10 % of the flattened scene's memory. With --moving,
every other node slides and turns while the shutter is open: moving instances
against moving copies (and --spp samples spread over the shutter). Part of
`make bench`, both ways.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "samples"))
from glb import with_json  # noqa: E402

COPIES = 210
STATS = re.compile(r"build (?P<build>[\d.]+) ms, render (?P<render>[\d.]+) ms")


def placed(source: bytes, shared: bool, moving: bool) -> bytes:
    """dragon_3's mesh drawn by COPIES nodes on a 15 x 14 grid, shared or one
    copy each; with `moving`, every other node moves by about 5 % of its
    length and turns by 0.1 rad while the shutter is open."""
    def edit(doc: dict) -> None:
        scene = doc["scenes"][doc.get("scene", 0)]
        mesh_nodes = [i for i, node in enumerate(doc["nodes"]) if "mesh" in node]
        mesh = doc["nodes"][mesh_nodes[0]]["mesh"]
        roots = [n for n in scene["nodes"] if n not in mesh_nodes]
        motions = []
        for k in range(COPIES):
            index = mesh
            if not shared and k > 0:
                doc["meshes"].append(json.loads(json.dumps(doc["meshes"][mesh])))
                index = len(doc["meshes"]) - 1
            angle = 0.2 * k
            translation = [1.2 * (k % 15), 0.0, -1.2 * (k // 15)]
            doc["nodes"].append({"name": f"dragon {k}", "mesh": index, "translation": translation,
                                 "rotation": [0.0, math.sin(angle), 0.0, math.cos(angle)]})
            roots.append(len(doc["nodes"]) - 1)
            if moving and k % 2 == 0:
                motions.append({"node": f"dragon {k}", "translation": [translation[0] + 0.05, 0.0, translation[2]],
                                "rotation": [0.0, math.sin(angle + 0.05), 0.0, math.cos(angle + 0.05)]})
        scene["nodes"] = roots
        if motions:
            doc["asset"].setdefault("extras", {}).setdefault("rt", {})["motions"] = motions
    return with_json(source, edit)


def run(rtrender: Path, scene: Path, out: Path, args: argparse.Namespace) -> dict[str, float]:
    """One rtrender run; its peak RSS from wait4, which reports that child's alone."""
    command = [str(rtrender), str(scene), "-o", str(out), "--quiet", "--width", str(args.width), "--height",
               str(args.height), "--samples-per-pixel", str(args.spp), "--threads", str(args.threads)]
    with tempfile.TemporaryFile("w+") as output:
        start = time.perf_counter()
        child = subprocess.Popen(command, stdout=output, stderr=subprocess.STDOUT, text=True)
        _, status, usage = os.wait4(child.pid, 0)
        wall = time.perf_counter() - start
        output.seek(0)
        text = output.read()
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError(f"rtrender failed on {scene.name}:\n{text}")
    match = STATS.search(text)
    if not match:
        raise RuntimeError(f"no build and render times in rtrender's output:\n{text}")
    return {"wall_s": wall, "peak_rss_mb": usage.ru_maxrss / 1024, "build_ms": float(match["build"]),
            "render_ms": float(match["render"])}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=Path, required=True)
    parser.add_argument("--rtrender", type=Path, required=True)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--spp", type=int, default=1)
    parser.add_argument("--threads", type=int, default=0, help="0: all cores")
    parser.add_argument("--moving", action="store_true", help="every other node moves while the shutter is open")
    args = parser.parse_args()
    source = (args.scenes / "dragon_3.glb").read_bytes()
    with tempfile.TemporaryDirectory() as folder:
        cases = {"shared": Path(folder) / "dragons_shared.glb", "copies": Path(folder) / "dragons_copies.glb"}
        for name, path in cases.items():
            path.write_bytes(placed(source, name == "shared", args.moving))
        results: dict[str, list[dict[str, float]]] = {name: [] for name in cases}
        for _ in range(args.runs):
            for name, path in cases.items():
                results[name].append(run(args.rtrender, path, Path(folder) / f"{name}.png", args))
        sizes = {name: path.stat().st_size for name, path in cases.items()}
    motion = ", every other one moving" if args.moving else ""
    print(f"instancing: dragon_3.glb placed {COPIES} times{motion}, {args.width}x{args.height}, {args.spp} spp, "
          f"threads {args.threads or 'all'}, {args.runs} runs in turns")
    medians: dict[str, dict[str, float]] = {}
    for name, runs in results.items():
        medians[name] = {key: statistics.median(r[key] for r in runs) for key in runs[0]}
        line = "   ".join(f"{key} {medians[name][key]:.3f} ({min(r[key] for r in runs):.3f}-{max(r[key] for r in runs):.3f})"
                          for key in runs[0])
        print(f"  {name:<6} file {sizes[name] / 1e6:.2f} MB   {line}")
    for key in medians["shared"]:
        print(f"  shared / copies {key}: {medians['shared'][key] / medians['copies'][key]:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
