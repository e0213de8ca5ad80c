#!/usr/bin/env python3
"""Write the test assets: the per-feature glTFs of docs/gltf.md and the
product-like model, into one folder (make assets; tests read RT_ASSETS_DIR).

Cheap to rerun: a file is rewritten only when its bytes change.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import feature_assets as feature  # noqa: E402
import structure_assets as structure  # noqa: E402
from product_model import product_model  # noqa: E402

# File name -> maker, which returns the file's bytes, or {name: bytes} for a
# file with others beside it. Every file is small (a few kB).
ASSETS = {
    "texture_transform.glb": feature.texture_transform,
    "vertex_colors.glb": feature.vertex_colors,
    "alpha_modes.glb": feature.alpha_modes,
    "emission.glb": feature.emission,
    "metallic_roughness.glb": feature.metallic_roughness,
    "normal_map.glb": feature.normal_map,
    "double_sided.glb": feature.double_sided,
    "strips_and_fans.glb": structure.strips_and_fans,
    "samplers.glb": feature.samplers,
    "image_formats.glb": feature.image_formats,
    "lights.glb": feature.lights,
    "transmission.glb": feature.transmission,
    "unlit.glb": feature.unlit,
    "data_uris.gltf": structure.data_uris,
    "external.gltf": structure.external_files,
    "node_hierarchy.glb": structure.node_hierarchy,
    "points_and_lines.glb": structure.points_and_lines,
    "normal_map_tangents.glb": feature.normal_map_tangents,
    "sparse.glb": structure.sparse,
    "no_buffer_view.glb": structure.no_buffer_view,
    "skinned.glb": structure.skinned,
    "morph_targets.glb": structure.morph_targets,
    "animation.glb": structure.animation,
    "orthographic_camera.glb": structure.orthographic_camera,
}


def write_if_changed(path: Path, data: bytes) -> None:
    if path.exists() and path.read_bytes() == data:
        return
    temporary = path.with_name(path.name + ".tmp")
    temporary.write_bytes(data)
    temporary.replace(path)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    makers = dict(ASSETS, **{"product.glb": product_model})
    written = 0
    for name, make in makers.items():
        made = make()
        for file_name, data in (made if isinstance(made, dict) else {name: made}).items():
            write_if_changed(args.out / file_name, data)
            written += 1
    print(f"make_assets: {written} files in {args.out} ({time.perf_counter() - start:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
