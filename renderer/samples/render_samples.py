#!/usr/bin/env python3
"""Render every sample scene with rtrender (make run).

Each scene in --scenes is rendered to <out>/<stem>.png with its first camera,
and one line per scene repeats rtrender's summary line. Exits non-zero when any
scene fails, after trying them all.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_samples import OUTPUTS  # noqa: E402  (the list of scene files, in table order)

SCENE_SUFFIXES = (".obj", ".glb", ".gltf")


def scene_files(folder: Path, only: list[str]) -> list[Path]:
    scenes = [folder / name for name in OUTPUTS if name.endswith(SCENE_SUFFIXES)]
    if only:
        unknown = set(only) - {p.stem for p in scenes}
        if unknown:
            sys.exit(f"render_samples: no scene named {', '.join(sorted(unknown))}")
        scenes = [p for p in scenes if p.stem in only]
    missing = [p.name for p in scenes if not p.is_file()]
    if missing:
        sys.exit(f"render_samples: missing in {folder}: {', '.join(missing)} (run make samples)")
    return scenes


def summary_line(result: subprocess.CompletedProcess) -> str:
    """rtrender's last line of output (stdout first): its summary."""
    for text in (result.stdout, result.stderr):
        lines = [line.strip() for line in text.splitlines() if line.strip()]
        if lines:
            return lines[-1]
    return "(no output)"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=Path, required=True, help="folder make_samples.py wrote")
    parser.add_argument("--out", type=Path, required=True, help="folder for the PNG files")
    parser.add_argument("--rtrender", type=Path, required=True, help="the rtrender executable")
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--only", nargs="+", default=[], metavar="STEM",
                        help="render only these scenes (e.g. cornell dragon_4)")
    parser.add_argument("--rtrender-arg", action="append", default=[], metavar="ARG",
                        help="pass ARG on to rtrender, one word each: --rtrender-arg=--threads --rtrender-arg=2")
    args = parser.parse_args()

    if not (args.rtrender.is_file() and os.access(args.rtrender, os.X_OK)):
        sys.exit(f"render_samples: {args.rtrender} is not an executable (run make build)")
    scenes = scene_files(args.scenes, args.only)
    args.out.mkdir(parents=True, exist_ok=True)

    failed = []
    for scene in scenes:
        png = args.out / f"{scene.stem}.png"
        command = [str(args.rtrender), str(scene), "-o", str(png), "--width", str(args.width),
                   "--height", str(args.height), *args.rtrender_arg]
        start = time.perf_counter()
        result = subprocess.run(command, capture_output=True, text=True)
        seconds = time.perf_counter() - start
        if result.returncode != 0:
            failed.append(scene.stem)
            print(f"{scene.stem:<22} FAILED (exit {result.returncode}, {seconds:.1f} s): "
                  f"{summary_line(result)}", flush=True)
            continue
        if not png.is_file():
            failed.append(scene.stem)
            print(f"{scene.stem:<22} FAILED: rtrender exited 0 but wrote no {png}", flush=True)
            continue
        print(f"{scene.stem:<22} {summary_line(result)}", flush=True)

    print(f"render_samples: {len(scenes) - len(failed)} of {len(scenes)} scenes rendered to {args.out}"
          + (f"; failed: {', '.join(failed)}" if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
