"""Compressed bunnies (renderer/samples/compressed.py) render as the plain one,
to within what their quantization allows.

Each file quantizes positions to P bits over the bunny's extent E, so a vertex
moves by at most d = E / (2^P - 1) / 2. That moves two things in the image:
- edges (the silhouette, shadow borders) by d / w pixels, w the size of a
  pixel at the bunny: at one sample per pixel an edge crosses a pixel's centre
  with a probability of about p = min(1, 2 d / w), and the pixel then changes by
  its contrast c (its largest difference to a neighbour), so the squared error
  is about p * mean(c^2);
- shading, through the normals: the bunny has none in its file, so they come
  from its faces, whose directions turn by about d / l for an edge length l;
  a Lambert or Phong term changes by about as much.
So RMSE <= sqrt(4 p mean(c^2)) + 4 d / l, a factor of 4 (2 on the root) over
those estimates. For scale: the plain bunny against itself shifted by one
pixel differs by an RMSE of 0.038, by four pixels 0.084, and against an empty
frame 0.29, so a decoder that got indices, attribute ids or filters wrong
fails by far.
"""
import json
import math
import struct
import sys
from pathlib import Path

import numpy as np
import pytest

import rtcore
from rt import render_pb2

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "renderer" / "samples"))
from compressed import QUANTIZATION  # noqa: E402

SIZE = 256


def glb_accessor(path: Path, index: int) -> np.ndarray:
    """Accessor `index` of a plain GLB (tightly packed, in its BIN chunk)."""
    data = path.read_bytes()
    json_length = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + json_length])
    binary = data[20 + json_length + 8:]
    accessor = doc["accessors"][index]
    view = doc["bufferViews"][accessor["bufferView"]]
    dtype = {5123: np.uint16, 5125: np.uint32, 5126: np.float32}[accessor["componentType"]]
    width = {"SCALAR": 1, "VEC3": 3}[accessor["type"]]
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    return np.frombuffer(binary, dtype, accessor["count"] * width, start).reshape(-1, width)


def bunny_geometry(path: Path) -> tuple[float, float]:
    """The bunny's extent and median edge length, from the plain file."""
    data = path.read_bytes()
    doc = json.loads(data[20:20 + struct.unpack_from("<I", data, 12)[0]])
    primitive = doc["meshes"][0]["primitives"][0]
    positions = glb_accessor(path, primitive["attributes"]["POSITION"]).astype(np.float64)
    corners = positions[glb_accessor(path, primitive["indices"]).reshape(-1, 3)]
    extent = float((positions.max(axis=0) - positions.min(axis=0)).max())
    edges = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2)
    return extent, float(np.median(edges))


def pixel_size(camera: bytes, at: np.ndarray) -> float:
    c = render_pb2.Camera.FromString(camera)
    distance = float(np.linalg.norm(np.asarray(c.position) - at))
    return 2 * distance * math.tan(math.radians(c.fov_y) / 2) / SIZE


def edge_contrast(image: np.ndarray) -> float:
    """The mean over pixels of the squared largest difference to a neighbour:
    what a pixel changes by when an edge crosses it."""
    c = np.zeros(image.shape[:2])
    dx = np.abs(np.diff(image, axis=1)).max(axis=2)
    dy = np.abs(np.diff(image, axis=0)).max(axis=2)
    for part, d in ((np.s_[:, 1:], dx), (np.s_[:, :-1], dx), (np.s_[1:], dy), (np.s_[:-1], dy)):
        c[part] = np.maximum(c[part], d)
    return float(np.mean(c ** 2))


def render(path: Path, camera: bytes) -> np.ndarray:
    scene = rtcore.Scene.load(str(path))
    settings = render_pb2.RenderSettings(width=SIZE, height=SIZE).SerializeToString()
    return np.clip(scene.render(camera, settings), 0, 1)


@pytest.fixture(scope="module")
def reference(scenes_dir):
    plain = scenes_dir / "bunny.glb"
    camera = rtcore.Scene.load(str(plain)).default_camera
    return plain, camera, render(plain, camera)


@pytest.mark.parametrize("name", sorted(QUANTIZATION))
def test_compressed_bunny_renders_as_the_plain_one(name, reference, assets_dir):
    plain, camera, expected = reference
    path = assets_dir / name
    if not path.exists():
        pytest.fail(f"{path} missing: run `make samples`")
    assert rtcore.Scene.load(str(path)).triangle_count == rtcore.Scene.load(str(plain)).triangle_count

    extent, edge_length = bunny_geometry(plain)
    position_bits, _ = QUANTIZATION[name]
    moved = extent / (2 ** position_bits - 1) / 2
    w = pixel_size(camera, np.array([0.0, 0.5, 0.0]))
    flips = min(1.0, 2 * moved / w)
    contrast = edge_contrast(expected)
    bound = math.sqrt(4 * contrast * flips) + 4 * moved / edge_length

    image = render(path, camera)
    rmse = float(np.sqrt(np.mean((image - expected) ** 2)))
    print(f"{name}: RMSE {rmse:.5f} against the plain bunny (bound {bound:.5f}; {position_bits}-bit positions "
          f"move {moved / w:.3f} px, faces turn {moved / edge_length:.4f} rad; mean squared edge contrast "
          f"{contrast:.5f})")
    assert rmse <= bound
