#!/usr/bin/env python3
"""What alpha costs: the product-like model (an alpha-masked perforated shade)
against the same file with every material made OPAQUE, rendered by rtrender
in turns, so that both see the same machine load.

A masked scene runs the traversal with its hit filter (each candidate hit
looks up the texel's alpha); the opaque copy runs the plain traversal, the
one every scene without alpha gets. Prints medians and ranges of the render
time and their ratio. Part of `make bench`.
"""

from __future__ import annotations

import argparse
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "samples"))
from glb import with_json  # noqa: E402

RENDER = re.compile(r"render (?P<ms>[\d.]+) ms, (?P<mrays>[\d.]+) Mrays/s")


def make_opaque(doc: dict) -> None:
    """Every material OPAQUE (same geometry, same textures)."""
    for material in doc.get("materials", []):
        material.pop("alphaMode", None)
        material.pop("alphaCutoff", None)


def render_ms(rtrender: Path, scene: Path, out: Path, args: argparse.Namespace) -> float:
    result = subprocess.run(
        [str(rtrender), str(scene), "-o", str(out), "--quiet", "--width", str(args.width), "--height",
         str(args.height), "--samples-per-pixel", str(args.spp), "--threads", str(args.threads)],
        capture_output=True, text=True, check=True)
    match = RENDER.search(result.stdout + result.stderr)
    if not match:
        raise RuntimeError(f"no render time in rtrender's output:\n{result.stderr}")
    return float(match["ms"])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--assets", type=Path, required=True, help="make_assets.py's folder")
    parser.add_argument("--rtrender", type=Path, required=True)
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--spp", type=int, default=4)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()

    masked = args.assets / "product.glb"
    with tempfile.TemporaryDirectory() as folder:
        opaque = Path(folder) / "product_opaque.glb"
        opaque.write_bytes(with_json(masked.read_bytes(), make_opaque))
        times: dict[str, list[float]] = {"masked": [], "opaque": []}
        for _ in range(args.runs):
            for name, scene in (("masked", masked), ("opaque", opaque)):
                times[name].append(render_ms(args.rtrender, scene, Path(folder) / f"{name}.exr", args))
    print(f"alpha cost: product.glb, {args.width}x{args.height}, {args.spp} spp, {args.threads} thread(s), "
          f"{args.runs} runs in turns")
    for name, values in times.items():
        print(f"  {name:<7} median {statistics.median(values):8.1f} ms   range {min(values):.1f}-{max(values):.1f} ms")
    ratio = statistics.median(times["masked"]) / statistics.median(times["opaque"])
    print(f"  masked / opaque: {ratio:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
