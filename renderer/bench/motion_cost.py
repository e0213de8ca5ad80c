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
import sys
import tempfile
from pathlib import Path

from in_turns import add_render_arguments, median_ratio, print_medians, time_in_turns

MOTION = {"motions": [{"node": "dragon_2", "translation": [0.05, 0.0, 0.0]}]}


def motion_applied(stderr: str) -> None:
    if "motion" in stderr and "ignored" in stderr:
        raise RuntimeError(f"the motion was not applied:\n{stderr}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=Path, required=True)
    add_render_arguments(parser, threads=0)
    args = parser.parse_args()

    still = args.scenes / "dragon_2.glb"
    with tempfile.TemporaryDirectory() as folder:
        moving = Path(folder) / "dragon_2.glb"
        moving.symlink_to(still.resolve())
        (Path(folder) / "dragon_2.rt.json").write_text(json.dumps(MOTION))
        times = time_in_turns({"moving": moving, "still": still}, Path(folder), ".png", args, motion_applied)
    print(f"motion blur cost: dragon_2.glb translated by (0.05, 0, 0), {args.width}x{args.height}, {args.spp} spp, "
          f"threads {args.threads or 'all'}, {args.runs} runs in turns")
    print_medians(times)
    print(f"  moving / still: {median_ratio(times, 'moving', 'still'):.3f} (target <= 1.3)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
