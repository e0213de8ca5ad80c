#!/usr/bin/env python3
"""The 2020 report's performance table (Table 2) with our figures beside it.

The 2020 report is "CG Ray Tracing" (Pohl, Gokbulut, Bobe, October 2020), the
ray tracer this project started from (docs/origin.md). Each sample scene that
stands in for one of its rows is rendered by rtrender with the default settings
(max depth 5, 16 shadow samples per spherical light) on all cores, and its
summary line gives triangles, BVH depth, build and render time. The report
does not say its image size; we render 800x600.

Below it, the report's motion blur (16 whole renders with the look-at point
shifted, averaged: FRAMES) against one render whose samples each take their own
shutter time (TIME_SAMPLED), at the same number of camera rays per pixel.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

# (the report's row: name, triangles, render time, BVH levels), our scene file
REPORT_ROWS = [
    ("Cornell box", "32", "168 ms", "8", "cornell.obj"),
    ("Cornell box sphere light", "32", "48.5 s", "8", "cornell_sphere_light.obj"),
    ("Monkey", "968", "0.5 s", "11", "smooth_sphere.glb"),
    ("Dragon", "87K", "0.5 s", "12", "dragon_3.glb"),
    ("Teacup", "48K", "0.43 s", "12", "teapot.glb"),
    ("Donut", "320K", "6.5 s", "12", "donut.glb"),
]

SUMMARY = re.compile(
    r"(?P<tris>\d+) triangles.*depth (?P<depth>\d+) \((?P<simd>\w+) kernels\), build (?P<build>[\d.]+) ms, "
    r"render (?P<render>[\d.]+) ms, (?P<mrays>[\d.]+) Mrays/s")


def render(rtrender: Path, scene: Path, out: Path, width: int, height: int, *flags: str,
           image: str = "") -> dict[str, str]:
    result = subprocess.run(
        [str(rtrender), str(scene), "-o", str(out / f"{image or scene.stem}.png"), "--width", str(width),
         "--height", str(height), "--quiet", *flags],
        capture_output=True, text=True, check=False)
    match = SUMMARY.search(result.stdout + result.stderr)
    if result.returncode != 0 or not match:
        sys.exit(f"report_table: rtrender failed on {scene.name}: {result.stderr.strip()}")
    return match.groupdict()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=Path, required=True)
    parser.add_argument("--rtrender", type=Path, required=True)
    parser.add_argument("--width", type=int, default=800)
    parser.add_argument("--height", type=int, default=600)
    parser.add_argument("--out", type=Path, default=Path("build/bench"), help="folder for the rendered images")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    print(f"\nThe 2020 report, Table 2                   | here, {args.width}x{args.height}, all cores")
    print(f"{'scene':26}{'tris':>6}{'time':>9}{'lvls':>5}  | {'sample scene':26}{'tris':>8}{'depth':>6}"
          f"{'build ms':>10}{'render ms':>11}{'Mrays/s':>9}")
    for name, tris, time, levels, file in REPORT_ROWS:
        ours = render(args.rtrender, args.scenes / file, args.out, args.width, args.height)
        print(f"{name:26}{tris:>6}{time:>9}{levels:>5}  | {file:26}{ours['tris']:>8}{ours['depth']:>6}"
              f"{float(ours['build']):>10.1f}{float(ours['render']):>11.1f}{float(ours['mrays']):>9.2f}")

    print("\nMotion blur: cornell_motion.obj, camera look_shift (the 2020 report's look-at shift), 16 rays per pixel")
    scene = args.scenes / "cornell_motion.obj"
    for mode, flags in (("frames (the report's 16 renders)", ("--motion-blur", "frames")),
                        ("time_sampled (one render)", ("--motion-blur", "time_sampled", "--samples-per-pixel", "16"))):
        ours = render(args.rtrender, scene, args.out, args.width, args.height, "--camera", "look_shift", *flags,
                      image=f"cornell_motion_{mode.split()[0]}")
        print(f"{mode:34}{float(ours['render']):>11.1f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
