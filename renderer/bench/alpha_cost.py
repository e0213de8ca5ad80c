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
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "samples"))
from glb import with_json  # noqa: E402
from in_turns import add_render_arguments, median_ratio, print_medians, time_in_turns  # noqa: E402


def make_opaque(doc: dict) -> None:
    """Every material OPAQUE (same geometry, same textures)."""
    for material in doc.get("materials", []):
        material.pop("alphaMode", None)
        material.pop("alphaCutoff", None)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--assets", type=Path, required=True, help="make_assets.py's folder")
    add_render_arguments(parser, threads=1)
    args = parser.parse_args()

    masked = args.assets / "product.glb"
    with tempfile.TemporaryDirectory() as folder:
        opaque = Path(folder) / "product_opaque.glb"
        opaque.write_bytes(with_json(masked.read_bytes(), make_opaque))
        times = time_in_turns({"masked": masked, "opaque": opaque}, Path(folder), ".exr", args)
    print(f"alpha cost: product.glb, {args.width}x{args.height}, {args.spp} spp, {args.threads} thread(s), "
          f"{args.runs} runs in turns")
    print_medians(times)
    print(f"  masked / opaque: {median_ratio(times, 'masked', 'opaque'):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
