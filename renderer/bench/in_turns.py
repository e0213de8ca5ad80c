"""Renders by rtrender timed in turns: each run renders every case once, one
after the other, so that all cases see the same machine load. Shared by the
benchmarks that put a feature's cost against the same scene without it."""

from __future__ import annotations

import argparse
import re
import statistics
import subprocess
from pathlib import Path
from typing import Callable

RENDER = re.compile(r"render (?P<ms>[\d.]+) ms, (?P<mrays>[\d.]+) Mrays/s")


def add_render_arguments(parser: argparse.ArgumentParser, threads: int) -> None:
    parser.add_argument("--rtrender", type=Path, required=True)
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--spp", type=int, default=4)
    parser.add_argument("--threads", type=int, default=threads, help="0: all cores")


def render_ms(scene: Path, out: Path, args: argparse.Namespace, check: Callable[[str], None] | None = None) -> float:
    """rtrender's own render time for one image; `check` sees its stderr first."""
    result = subprocess.run(
        [str(args.rtrender), str(scene), "-o", str(out), "--quiet", "--width", str(args.width), "--height",
         str(args.height), "--samples-per-pixel", str(args.spp), "--threads", str(args.threads)],
        capture_output=True, text=True, check=True)
    if check:
        check(result.stderr)
    match = RENDER.search(result.stdout + result.stderr)
    if not match:
        raise RuntimeError(f"no render time in rtrender's output:\n{result.stderr}")
    return float(match["ms"])


def time_in_turns(cases: dict[str, Path], folder: Path, suffix: str, args: argparse.Namespace,
                  check: Callable[[str], None] | None = None) -> dict[str, list[float]]:
    """Render times of every case, args.runs each, taken in turns."""
    times: dict[str, list[float]] = {name: [] for name in cases}
    for _ in range(args.runs):
        for name, scene in cases.items():
            times[name].append(render_ms(scene, folder / f"{name}{suffix}", args, check))
    return times


def print_medians(times: dict[str, list[float]]) -> None:
    width = max(len(name) for name in times)
    for name, values in times.items():
        print(f"  {name:<{width}} median {statistics.median(values):8.1f} ms   range {min(values):.1f}-{max(values):.1f} ms")


def median_ratio(times: dict[str, list[float]], over: str, under: str) -> float:
    return statistics.median(times[over]) / statistics.median(times[under])
