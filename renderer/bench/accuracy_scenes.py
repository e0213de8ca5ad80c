"""Variants of the sample scenes that speed_accuracy.py needs, written as scene
folders of their own: a copy of the scene file and a sidecar `<stem>.rt.json`
(rt.SceneExtras, proto/rt/scene.proto).

- the dragon lit by a spherical light instead of its glTF point light;
- the dragon turning and sliding while the shutter is open (an rt.NodeMotion);
- the Cornell box with two reflective spheres, so that reflections of
  reflections (max_depth above 1) and the min_contribution cutoff matter.
"""

from __future__ import annotations

import json
import shutil
import struct
from pathlib import Path

import numpy as np

LIGHTS_EXT = "KHR_lights_punctual"
_JSON_CHUNK = 0x4E4F534A


def read_glb(path: Path) -> tuple[dict, bytes]:
    """(the glTF JSON, every chunk after it, as stored)."""
    data = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    json_length, json_type = struct.unpack_from("<II", data, 12)
    if magic != b"glTF" or version != 2 or length != len(data) or json_type != _JSON_CHUNK:
        raise ValueError(f"{path}: not a binary glTF 2.0 file")
    return json.loads(data[20:20 + json_length]), data[20 + json_length:]


def write_glb(path: Path, gltf: dict, rest: bytes) -> None:
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<II", len(text), _JSON_CHUNK) + text + rest
    path.write_bytes(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)


def _point_light(gltf: dict) -> tuple[int, list[float], float]:
    """(node index, position, intensity) of the file's one point light."""
    lights = gltf.get("extensions", {}).get(LIGHTS_EXT, {}).get("lights", [])
    for index, node in enumerate(gltf["nodes"]):
        light = node.get("extensions", {}).get(LIGHTS_EXT, {}).get("light")
        if light is not None:
            color = lights[light].get("color", [1.0, 1.0, 1.0])
            if len(set(color)) != 1:
                raise ValueError("the point light is coloured: only white lights are moved to the sidecar")
            return index, [float(c) for c in node["translation"]], float(lights[light]["intensity"]) * color[0]
    raise ValueError("the glTF file has no point light")


def model_extent(gltf: dict, node_name: str) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of a mesh node's POSITION accessors (the glTF requires their min/max)."""
    node = next(n for n in gltf["nodes"] if n.get("name") == node_name)
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for primitive in gltf["meshes"][node["mesh"]]["primitives"]:
        accessor = gltf["accessors"][primitive["attributes"]["POSITION"]]
        lo, hi = np.minimum(lo, accessor["min"]), np.maximum(hi, accessor["max"])
    return lo, hi


def _make_folder(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def sphere_lit_glb(source: Path, folder: Path, radius_per_extent: float = 0.25) -> tuple[Path, dict]:
    """A copy of a sample model scene whose point light becomes a spherical
    light at the same place and of the same intensity, with a radius of
    `radius_per_extent` times the model's largest extent (the ground plane
    left out). Returns the scene file and the light."""
    gltf, rest = read_glb(source)
    index, position, intensity = _point_light(gltf)
    del gltf["nodes"][index]["extensions"]  # the node stays, empty; its light is no longer placed
    lo, hi = model_extent(gltf, source.stem)
    light = {"position": position, "color": [1.0, 1.0, 1.0], "intensity": intensity,
             "radius": round(float(radius_per_extent * np.max(hi - lo)), 4)}
    folder = _make_folder(folder)
    scene = folder / source.name
    write_glb(scene, gltf, rest)
    (folder / f"{source.stem}.rt.json").write_text(json.dumps({"lights": [light]}, indent=2) + "\n")
    return scene, light


def moving_glb(source: Path, folder: Path, turn_degrees: float = 4.0,
               slide_per_extent: float = 0.05) -> tuple[Path, dict]:
    """A copy of a sample model scene whose model (the node named after the
    file) turns about +Y and slides along +X while the shutter is open
    (returns the scene file and the rt.NodeMotion, with turn_degrees). The
    motion is kept small: moving triangles' boxes grow with it, and a 12-degree
    turn made the dragon's renders 6 times slower than the still dragon's."""
    gltf, _ = read_glb(source)
    lo, hi = model_extent(gltf, source.stem)
    half = np.radians(turn_degrees) / 2
    motion = {"node": source.stem,
              "translation": [round(float(slide_per_extent * np.max(hi - lo)), 4), 0.0, 0.0],
              "rotation": [0.0, round(float(np.sin(half)), 7), 0.0, round(float(np.cos(half)), 7)]}
    folder = _make_folder(folder)
    scene = folder / source.name
    shutil.copyfile(source, scene)
    (folder / f"{source.stem}.rt.json").write_text(json.dumps({"motions": [motion]}, indent=2) + "\n")
    return scene, {**motion, "turn_degrees": turn_degrees}


# In the unit Cornell box (x, z in [-0.5, 0.5], y in [0, 1]): a mirror ball on
# the short box and a glossy ball on the floor in front of the tall one, both in
# view of the mirror panel on the red wall, so rays bounce between the three.
REFLECTIVE_SPHERES = [
    {"center": [0.17, 0.42, 0.12], "radius": 0.12,
     "material": {"diffuse": [0.05, 0.05, 0.05], "specular": [0.2, 0.2, 0.2], "shininess": 500,
                  "reflectance": [0.85, 0.85, 0.85]}},
    {"center": [-0.22, 0.1, 0.25], "radius": 0.1,
     "material": {"diffuse": [0.5, 0.35, 0.1], "specular": [0.3, 0.3, 0.3], "shininess": 100,
                  "reflectance": [0.3, 0.3, 0.3]}},
]


def cornell_with_spheres(scenes: Path, folder: Path) -> Path:
    """cornell.obj with its sidecar's lights and cameras, plus REFLECTIVE_SPHERES."""
    folder = _make_folder(folder)
    for name in ("cornell.obj", "cornell.mtl"):
        shutil.copyfile(scenes / name, folder / name)
    extras = json.loads((scenes / "cornell.rt.json").read_text())
    extras["spheres"] = REFLECTIVE_SPHERES
    (folder / "cornell.rt.json").write_text(json.dumps(extras, indent=2) + "\n")
    return folder / "cornell.obj"
