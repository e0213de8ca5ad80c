#!/usr/bin/env python3
"""Resident memory of the product-like model with its six maps at 4096²
(renderer/samples/product_model.py), loaded through rtcore: the textures'
bytes against their 8-bit texels, and how far the process grew. Part of
`make bench` (writing the maps takes a while; the 1.4x bound itself is
tested on five 4096² maps in tests/renderer/test_texture_memory.py).
"""

from __future__ import annotations

import argparse
import io
import json
import resource
import struct
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "renderer" / "samples"))

import rtcore  # noqa: E402
from PIL import Image  # noqa: E402
from product_model import product_model  # noqa: E402


def eight_bit_bytes(glb: bytes) -> tuple[int, int]:
    """The images' texel bytes at 8 bits a channel, and how many images."""
    length, _ = struct.unpack_from("<II", glb, 12)
    doc = json.loads(glb[20:20 + length])
    binary = glb[20 + length + 8:]
    total = 0
    for image in doc["images"]:
        view = doc["bufferViews"][image["bufferView"]]
        start = view.get("byteOffset", 0)
        with Image.open(io.BytesIO(binary[start:start + view["byteLength"]])) as decoded:
            total += decoded.width * decoded.height * len(decoded.getbands())
    return total, len(doc["images"])


def rss_bytes() -> int:
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    raise RuntimeError("no VmRSS in /proc/self/status")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=4096)
    args = parser.parse_args()
    start = time.perf_counter()
    data = product_model(args.size)
    made = time.perf_counter() - start
    texels, maps = eight_bit_bytes(data)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "product.glb"
        path.write_bytes(data)
        del data
        before = rss_bytes()
        start = time.perf_counter()
        scene = rtcore.Scene.load(str(path))
        loaded = time.perf_counter() - start
        growth = rss_bytes() - before
    print(f"product.glb with {maps} maps at {args.size}²: file made in {made:.1f} s, loaded in {loaded:.1f} s")
    print(f"  textures {scene.texture_bytes / 2**20:.1f} MiB with mips, {texels / 2**20:.0f} MiB of 8-bit texels: "
          f"{scene.texture_bytes / texels:.3f}x")
    print(f"  resident memory grew by {growth / 2**20:.1f} MiB on loading; peak RSS "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**10:.0f} MiB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
