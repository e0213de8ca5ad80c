#!/usr/bin/env python3
"""What motion blur costs: dragon_2 moving by (0.05, 0, 0) while the shutter is
open (a sidecar NodeMotion on node dragon_2, about 5 % of its length) against
the same still scene, rendered by rtrender in turns so that both see the same
machine load. Issue 16's target: at most 1.3x the still render.

Prints medians and ranges of the render time and their ratio. Part of `make bench`.
"""

from __future__ import annotations

import argparse
import json
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

RENDER = re.compile(r"render (?P<ms>[\d.]+) ms, (?P<mrays>[\d.]+) Mrays/s")
MOTION = {"motions": [{"node": "dragon_2", "translation": [0.05, 0.0, 0.0]}]}


def render_ms(rtrender: Path, scene: Path, out: Path, args: argparse.Namespace) -> float:
    result = subprocess.run(
        [str(rtrender), str(scene), "-o", str(out), "--quiet", "--width", str(args.width), "--height",
         str(args.height), "--samples-per-pixel", str(args.spp), "--threads", str(args.threads)],
        capture_output=True, text=True, check=True)
    if "motion" in result.stderr and "ignored" in result.stderr:
        raise RuntimeError(f"the motion was not applied:\n{result.stderr}")
    match = RENDER.search(result.stdout + result.stderr)
    if not match:
        raise RuntimeError(f"no render time in rtrender's output:\n{result.stderr}")
    return float(match["ms"])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=Path, required=True)
    parser.add_argument("--rtrender", type=Path, required=True)
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--spp", type=int, default=4)
    parser.add_argument("--threads", type=int, default=0, help="0: all cores")
    args = parser.parse_args()

    still = args.scenes / "dragon_2.glb"
    with tempfile.TemporaryDirectory() as folder:
        moving = Path(folder) / "dragon_2.glb"
        moving.symlink_to(still.resolve())
        (Path(folder) / "dragon_2.rt.json").write_text(json.dumps(MOTION))
        times: dict[str, list[float]] = {"moving": [], "still": []}
        for _ in range(args.runs):
            for name, scene in (("moving", moving), ("still", still)):
                times[name].append(render_ms(args.rtrender, scene, Path(folder) / f"{name}.png", args))
    print(f"motion blur cost: dragon_2.glb translated by (0.05, 0, 0), {args.width}x{args.height}, {args.spp} spp, "
          f"threads {args.threads or 'all'}, {args.runs} runs in turns")
    for name, values in times.items():
        print(f"  {name:<6} median {statistics.median(values):8.1f} ms   range {min(values):.1f}-{max(values):.1f} ms")
    ratio = statistics.median(times["moving"]) / statistics.median(times["still"])
    print(f"  moving / still: {ratio:.3f} (target <= 1.3)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
