#!/usr/bin/env python3
"""Write the hostile loader corpus, and seeds for the fuzz targets.

    make_corpus.py --out DIR                     the corpus (CMake does this for rt_tests)
    make_corpus.py --seeds DIR [--samples DIR]   seeds for fuzz_gltf, fuzz_glb, fuzz_obj, fuzz_sidecar

The corpus is DIR/scenes/, every file there broken in one way (truncated, lying
lengths, huge counts, non-finite numbers, references out of the folder, cycles,
deep nesting, ...), beside the companion files the references may name (the
same as the fuzz targets' folder, renderer/fuzz/fuzz_folder.h), with
DIR/outside.* one level up for escapes to aim at. DIR/manifest.tsv has one row
per scene file: its name, what the loader must do (error: throw SceneError
naming the file; loads: load, with a warning containing the text when one is
given; any: either, but never crash) and a text the error must contain.
LoaderCorpus.* (renderer/tests/loader_corpus_test.cpp) loads them all.

Only the standard library: it runs before any venv exists. Deterministic.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import struct
import sys
from pathlib import Path

from corpus import build
from corpus.bases import TRIANGLE_BIN, Corpus, data_uri

MTL_SEPARATOR = b"\n#%mtl\n"  # fuzz_obj.cpp: OBJ text, then fuzz.mtl's


# --- Writing -------------------------------------------------------------------

def write_corpus(c: Corpus, out: Path) -> None:
    if out.exists():
        if any(out.iterdir()) and not (out / "manifest.tsv").exists() and not (out / "scenes").is_dir():
            sys.exit(f"{out} exists and is not a corpus folder: not replacing it")
        shutil.rmtree(out)
    scenes = out / "scenes"
    for name, data in c.files.items():
        path = scenes / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    (scenes / "folder.bin").mkdir()
    os.symlink("..", scenes / "escape")
    (out / "outside.bin").write_bytes(TRIANGLE_BIN)
    (out / "outside.mtl").write_bytes(b"newmtl plain\nKd 1 0 0\n")
    # Written last: CMake takes it for the whole corpus.
    rows = "".join(f"{name}\t{expect}\t{mentions}\n" for name, expect, mentions in c.rows)
    (out / "manifest.tsv").write_text("# file\texpect (error, loads, any)\ttext the message must contain\n" + rows)


def glb_as_gltf(data: bytes) -> bytes | None:
    """A sample .glb as a .gltf with its BIN chunk as a data: URI."""
    try:
        json_length = struct.unpack_from("<I", data, 12)[0]
        doc = json.loads(data[20:20 + json_length])
        rest = data[20 + json_length:]
        bin_chunk = rest[8:8 + struct.unpack_from("<I", rest, 0)[0]] if len(rest) >= 8 else b""
        doc["buffers"][0]["uri"] = data_uri(bin_chunk[:doc["buffers"][0]["byteLength"]])
        return json.dumps(doc).encode()
    except (ValueError, KeyError, IndexError, struct.error):
        return None


def with_mtl(obj_text: bytes, mtl: bytes | None) -> bytes:
    """An OBJ as fuzz_obj.cpp takes it: its material library as fuzz.mtl after the separator."""
    if mtl is None:
        return obj_text
    lines = [b"mtllib fuzz.mtl" if line.startswith(b"mtllib ") else line for line in obj_text.split(b"\n")]
    return b"\n".join(lines) + MTL_SEPARATOR + mtl


def write_seeds(c: Corpus, seeds: Path, samples: Path | None, max_bytes: int = 65536) -> None:
    """One folder per fuzz target (replaced), each file named by its content."""
    for target in ("gltf", "glb", "obj", "sidecar"):
        shutil.rmtree(seeds / target, ignore_errors=True)

    def put(target: str, data: bytes) -> None:
        if len(data) <= max_bytes:
            folder = seeds / target
            folder.mkdir(parents=True, exist_ok=True)
            (folder / hashlib.sha1(data).hexdigest()).write_bytes(data)

    for name, data in c.files.items():
        stem, ext = os.path.splitext(name)
        if ext == ".gltf":
            put("gltf", data)
        elif ext == ".glb":
            put("glb", data)
        elif ext == ".obj" and not stem.startswith("sidecar_"):
            mtl_name = next((line.split(b" ", 1)[1].decode(errors="replace").strip()
                             for line in data.split(b"\n") if line.startswith(b"mtllib ")), None)
            put("obj", with_mtl(data, c.files.get(mtl_name) if mtl_name else None))
        elif name.endswith(".rt.json"):
            put("sidecar", data)
    if samples and samples.is_dir():
        for path in sorted(samples.glob("*.glb")):
            if path.stat().st_size <= max_bytes:
                data = path.read_bytes()
                put("glb", data)
                converted = glb_as_gltf(data)
                if converted:
                    put("gltf", converted)
        for path in sorted(samples.glob("*.obj")):
            mtl = path.with_suffix(".mtl")
            put("obj", with_mtl(path.read_bytes(), mtl.read_bytes() if mtl.exists() else None))
        for path in sorted(samples.glob("*.rt.json")):
            put("sidecar", path.read_bytes())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, help="write the corpus here (replaced)")
    parser.add_argument("--seeds", type=Path, help="write fuzz seeds here, one folder per target")
    parser.add_argument("--samples", type=Path, help="sample scenes to add to the seeds (build/scenes)")
    args = parser.parse_args()
    if not args.out and not args.seeds:
        parser.error("nothing to do: give --out, --seeds or both")
    corpus = build()
    if args.out:
        write_corpus(corpus, args.out)
        print(f"{len(corpus.rows)} hostile scene files in {args.out / 'scenes'}")
    if args.seeds:
        write_seeds(corpus, args.seeds, args.samples)


if __name__ == "__main__":
    main()
