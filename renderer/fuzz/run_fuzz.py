#!/usr/bin/env python3
"""Run the loaders' libFuzzer targets for a fixed time each (make fuzz).

    run_fuzz.py --build build/fuzz --seeds build/fuzz/seeds --seconds 15

Each target runs on its own growing corpus (BUILD/corpus/<target>, kept between
runs) seeded with SEEDS/<target> (make_corpus.py --seeds), with the dictionary
renderer/fuzz/<target>.dict when there is one, as many at once as --jobs. Any
crash, sanitizer report, leak, timeout or memory blow-up fails the run; libFuzzer
keeps the input in BUILD/crashes/<target>-crash-<sha1> (or -leak-, -timeout-,
-oom-) and the whole output in BUILD/logs/<target>.log. Prints executions per
second and in total for each target.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

HERE = Path(__file__).resolve().parent
TARGETS = ["gltf", "glb", "obj", "sidecar"]
DICTIONARIES = {"gltf": "gltf.dict", "glb": "gltf.dict", "obj": "obj.dict", "sidecar": "sidecar.dict"}


def minimize(binary: Path, corpus: Path, text: str, env: dict, args: argparse.Namespace) -> None:
    """Replaces the corpus by a merge of it once it holds half again as many files
    as libFuzzer kept in memory: reduced inputs are added beside the ones they
    replace, and loading them all would take the next short run's time."""
    kept = re.findall(r"corp: (\d+)/", text)
    files = sum(1 for _ in corpus.iterdir())
    if not kept or files <= 1.5 * int(kept[-1]) + 100:
        return
    merged = corpus.with_name(corpus.name + ".merging")
    shutil.rmtree(merged, ignore_errors=True)
    merged.mkdir()
    command = [str(binary), "-merge=1", f"-timeout={args.timeout}", f"-max_len={args.max_len}", str(merged),
               str(corpus)]
    try:
        result = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                                timeout=args.seconds * 3 + 120)
        if result.returncode == 0 and any(merged.iterdir()):
            shutil.rmtree(corpus)
            merged.rename(corpus)
    except subprocess.TimeoutExpired:
        pass
    shutil.rmtree(merged, ignore_errors=True)


def run_target(target: str, args: argparse.Namespace) -> dict:
    build = args.build.resolve()
    binary = build / "fuzz" / f"fuzz_{target}"
    corpus = build / "corpus" / target
    crashes = build / "crashes"
    logs = build / "logs"
    for folder in (corpus, crashes, logs):
        folder.mkdir(parents=True, exist_ok=True)
    command = [str(binary), str(corpus)]
    seeds = args.seeds.resolve() / target if args.seeds else None
    if seeds and seeds.is_dir():
        command.append(str(seeds))
    command += [
        f"-max_total_time={args.seconds}", f"-timeout={args.timeout}", "-rss_limit_mb=2560",
        f"-max_len={args.max_len}", "-print_final_stats=1", f"-artifact_prefix={crashes}/{target}-",
    ]
    if target in DICTIONARIES:
        command.append(f"-dict={HERE / DICTIONARIES[target]}")
    # The targets' scene folder (fuzz_folder.h), in memory, removed whatever happens.
    shm = "/dev/shm" if os.path.isdir("/dev/shm") else None
    scratch = tempfile.mkdtemp(prefix=f"rt_fuzz_{target}_", dir=shm)
    env = dict(os.environ, RT_FUZZ_TMP=scratch,
               ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:" + os.environ.get("ASAN_OPTIONS", ""),
               UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:" + os.environ.get("UBSAN_OPTIONS", ""))
    log = logs / f"{target}.log"
    start = time.monotonic()
    try:
        with open(log, "wb") as out:
            # A little over the fuzzing time: libFuzzer loads the corpus first.
            result = subprocess.run(command, stdout=out, stderr=subprocess.STDOUT, env=env, cwd=build,
                                    timeout=args.seconds * 3 + 120)
        returncode = result.returncode
        seconds = time.monotonic() - start
        text = log.read_text(errors="replace")
        if returncode == 0:
            minimize(binary, corpus, text, env, args)
    except subprocess.TimeoutExpired:
        returncode, seconds, text = -1, time.monotonic() - start, log.read_text(errors="replace")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    stat = lambda name: int(m.group(1)) if (m := re.search(rf"stat::{name}:\s+(\d+)", text)) else 0  # noqa: E731
    coverage = re.findall(r"cov: (\d+)", text)
    artifacts = re.findall(r"Test unit written to (\S+)", text)
    return {"target": target, "returncode": returncode, "seconds": seconds,
            "runs": stat("number_of_executed_units"), "per_second": stat("average_exec_per_sec"),
            "new": stat("new_units_added"), "coverage": int(coverage[-1]) if coverage else 0,
            "corpus": sum(1 for _ in corpus.iterdir()), "artifacts": artifacts, "log": log, "text": text}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", type=Path, default=Path("build/fuzz"), help="the RT_FUZZ=ON CMake tree")
    parser.add_argument("--seeds", type=Path, help="seed folders, one per target (make_corpus.py --seeds)")
    parser.add_argument("--seconds", type=int, default=15, help="fuzzing time per target")
    parser.add_argument("--timeout", type=int, default=30, help="seconds one input may take")
    parser.add_argument("--max-len", type=int, default=65536, help="largest input in bytes")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="targets run at once")
    parser.add_argument("targets", nargs="*", help=f"some of {', '.join(TARGETS)} (default: all)")
    args = parser.parse_args()
    args.targets = args.targets or TARGETS
    for target in args.targets:
        if target not in TARGETS:
            parser.error(f"unknown target {target!r}: expected one of {', '.join(TARGETS)}")
        if not (args.build / "fuzz" / f"fuzz_{target}").is_file():
            parser.error(f"{args.build}/fuzz/fuzz_{target} is not built")

    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = list(pool.map(lambda t: run_target(t, args), args.targets))

    print(f"{'target':<14}{'seconds':>9}{'runs':>11}{'exec/s':>9}{'cov':>7}{'new':>6}{'corpus':>8}  result")
    failed = False
    for r in results:
        ok = r["returncode"] == 0 and not r["artifacts"]
        failed = failed or not ok
        print(f"{'fuzz_' + r['target']:<14}{r['seconds']:>9.1f}{r['runs']:>11}{r['per_second']:>9}{r['coverage']:>7}"
              f"{r['new']:>6}{r['corpus']:>8}  {'ok' if ok else 'FAILED (exit %d)' % r['returncode']}")
    for r in results:
        if r["returncode"] == 0 and not r["artifacts"]:
            continue
        report = [line for line in r["text"].splitlines()
                  if re.search(r"ERROR|SUMMARY|contract broken|runtime error|#\d+ 0x", line)]
        print(f"\nfuzz_{r['target']} failed; full output in {r['log']}", file=sys.stderr)
        print("\n".join(report[:40]), file=sys.stderr)
        for artifact in r["artifacts"]:
            print(f"input kept in {artifact}; replay: {args.build}/fuzz/fuzz_{r['target']} {artifact}",
                  file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
