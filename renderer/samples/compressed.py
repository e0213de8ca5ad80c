#!/usr/bin/env python3
"""Write the compressed bunnies (from --scenes/bunny.glb) and the WebP product model into --out (make samples).

    bunny_draco.glb      gltf-pipeline -d             (KHR_draco_mesh_compression)
    bunny_meshopt.glb    gltf-transform meshopt       (EXT_meshopt_compression, KHR_mesh_quantization)
    bunny_quantized.glb  gltf-transform quantize      (KHR_mesh_quantization)
    product_webp.glb     gltf-transform webp          (EXT_texture_webp, from make_assets.py's product.glb)

They go beside the test assets, not the sample scenes, so that the viewer's
scene list (every .glb of the scenes folder) stays as it was. The tools are the
npm packages of package.json, installed by make_samples.py (npm ci
--ignore-scripts: neither CLI needs an install script for these commands).
Cached: nothing runs while the stamp's hash of bunny.glb, this script and
package-lock.json is current and every output exists.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
BIN = HERE / "node_modules" / ".bin"
STAMP = ".compressed.stamp"


# Bits of (position, normal) quantization each output asks for, given
# explicitly (they are the tools' defaults) because tests/renderer/
# test_compressed.py derives its error bounds from them.
QUANTIZATION = {"bunny_draco.glb": (11, 8), "bunny_meshopt.glb": (14, 10), "bunny_quantized.glb": (14, 10)}


def commands(source: Path, target: Path) -> dict[str, list[str]]:
    """Each output's command line, writing to `target`."""
    draco_bits = QUANTIZATION["bunny_draco.glb"]
    transform_bits = [("--quantize-position", str(QUANTIZATION[name][0]), "--quantize-normal",
                       str(QUANTIZATION[name][1])) for name in ("bunny_meshopt.glb", "bunny_quantized.glb")]
    return {
        "bunny_draco.glb": [str(BIN / "gltf-pipeline"), "-i", str(source), "-o", str(target), "-d",
                            "--draco.quantizePositionBits", str(draco_bits[0]),
                            "--draco.quantizeNormalBits", str(draco_bits[1])],
        "bunny_meshopt.glb": [str(BIN / "gltf-transform"), "meshopt", str(source), str(target),
                              *transform_bits[0]],
        "bunny_quantized.glb": [str(BIN / "gltf-transform"), "quantize", str(source), str(target),
                                *transform_bits[1]],
        # Lossless, so that the WebP textures decode to the PNGs' texels.
        "product_webp.glb": [str(BIN / "gltf-transform"), "webp", str(target.parent / "product.glb"), str(target),
                             "--lossless", "true"],
    }


def draco_compress(source: Path, target: Path, position_bits: int = 11) -> None:
    """`source` glTF as a Draco-compressed GLB at `target` (gltf-pipeline's
    defaults but for `position_bits`)."""
    run({target.name: [str(BIN / "gltf-pipeline"), "-i", str(source), "-o", str(target), "-d",
                       "--draco.quantizePositionBits", str(position_bits)]}, target.parent)


def run(jobs: dict[str, list[str]], out: Path) -> None:
    """Runs the commands at once (each is a second of Node start-up, mostly),
    each writing to a temporary name renamed into place when it succeeds."""
    running = []
    for name, command in jobs.items():
        temp = out / f".{name}.tmp.{os.getpid()}.glb"
        command = [temp.as_posix() if part == str(out / name) else part for part in command]
        running.append((name, temp, command, subprocess.Popen(command, stdout=subprocess.PIPE,
                                                              stderr=subprocess.STDOUT, text=True)))
    failed = []
    for name, temp, command, process in running:
        output, _ = process.communicate()
        if process.returncode == 0 and temp.is_file():
            os.replace(temp, out / name)
        else:
            temp.unlink(missing_ok=True)
            failed.append(f"`{' '.join(Path(command[0]).name if i == 0 else p for i, p in enumerate(command))}`"
                          f" failed:\n{output}")
    if failed:
        sys.exit("compressed: " + "\n".join(failed))


def inputs_hash(source: Path, product: Path) -> str:
    digest = hashlib.sha256()
    for path in (source, product, Path(__file__), HERE / "package-lock.json"):
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=Path, required=True, help="the sample scenes (holding bunny.glb)")
    parser.add_argument("--out", type=Path, required=True, help="folder for the compressed files")
    args = parser.parse_args()
    source, product = args.scenes / "bunny.glb", args.out / "product.glb"
    if not source.is_file():
        sys.exit(f"compressed: {source} is missing: run make_samples.py first")
    if not product.is_file():
        sys.exit(f"compressed: {product} is missing: run make_assets.py first")
    sys.path.insert(0, str(HERE))
    from make_samples import ensure_node_modules  # noqa: E402
    ensure_node_modules()

    digest = inputs_hash(source, product)
    stamp = args.out / STAMP
    jobs = commands(source, args.out / "NAME")
    try:
        if json.loads(stamp.read_text()).get("hash") == digest and all((args.out / n).is_file() for n in jobs):
            print(f"compressed: {args.out} is up to date")
            return 0
    except (OSError, ValueError, AttributeError):
        pass
    args.out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    run({name: commands(source, args.out / name)[name] for name in jobs}, args.out)
    stamp.write_text(json.dumps({"hash": digest}))
    sizes = ", ".join(f"{name} {(args.out / name).stat().st_size / 1e3:.1f} KB" for name in jobs)
    print(f"compressed: {sizes} ({time.perf_counter() - start:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
