"""The feature assets of docs/gltf.md about how a file is put together rather
than what its surfaces look like: primitive modes (strips, fans, points,
lines), data inline or in files beside it, a node hierarchy, sparse accessors
and one without a buffer view, a skin, morph targets, an animation and an
orthographic camera.

They are built from feature_assets.py's helpers, so each stays the same quad
with one thing changed; their asset.generator still names feature_assets.py,
which keeps every file byte-identical to the one the tests and the three.js
peer check have always loaded.
"""

from __future__ import annotations

import base64
import json

import numpy as np

from feature_assets import QUAD_POSITIONS, checker, pbr, quad, textured, with_texture
from glb import GlbBuilder


def strips_and_fans() -> bytes:
    """The quad as a TRIANGLE_STRIP and as a TRIANGLE_FAN."""
    b = GlbBuilder("rt feature_assets.py")
    material = b.add_material(pbr((0.3, 0.5, 0.9, 1.0)))
    quad(b, "strip", material, (-1.1, 0, 0))
    quad(b, "fan", material, (1.1, 0, 0))
    strip, fan = (b.gltf["meshes"][i]["primitives"][0] for i in (0, 1))
    strip["mode"], fan["mode"] = 5, 6
    strip["indices"] = b._accessor(np.array([0, 1, 3, 2], "<u4"), "SCALAR", 5125, 34963)
    fan["indices"] = b._accessor(np.array([0, 1, 2, 3], "<u4"), "SCALAR", 5125, 34963)
    return b.to_bytes()


def data_uris() -> bytes:
    """A .gltf whose buffer and image are both data URIs."""
    b = GlbBuilder("rt feature_assets.py")
    texture = textured(b, checker())
    quad(b, "inline", b.add_material(with_texture(pbr(), "baseColorTexture", {"index": texture})))
    b.bin.extend(b"\0" * (-len(b.bin) % 4))
    doc = b.gltf
    image = doc["images"][0]
    view = doc["bufferViews"][image.pop("bufferView")]
    png = bytes(b.bin[view["byteOffset"]:view["byteOffset"] + view["byteLength"]])
    image["uri"] = "data:image/png;base64," + base64.b64encode(png).decode()
    image.pop("mimeType")
    doc["buffers"] = [{"byteLength": len(b.bin),
                       "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(b.bin)).decode()}]
    return json.dumps(doc).encode()


def external_files() -> dict[str, bytes]:
    """A .gltf with its buffer and its image in files of their own."""
    doc = json.loads(data_uris())
    buffer = base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1])
    image = base64.b64decode(doc["images"][0]["uri"].split(",", 1)[1])
    doc["buffers"][0]["uri"], doc["images"][0]["uri"] = "external.bin", "external_checker.png"
    return {"external.gltf": json.dumps(doc).encode(), "external.bin": buffer, "external_checker.png": image}


def node_hierarchy() -> bytes:
    """A parent with a matrix and two TRS children, one of them nested again."""
    b = GlbBuilder("rt feature_assets.py")
    quad(b, "child_a", b.add_material(pbr((0.8, 0.4, 0.1, 1.0))))
    quad(b, "grandchild", b.add_material(pbr((0.1, 0.6, 0.8, 1.0))))
    nodes = b.gltf["nodes"]
    nodes[0].update(translation=[-1.2, 0.0, 0.0], scale=[0.5, 0.5, 0.5], children=[1])
    nodes[1].update(translation=[4.0, 0.0, 0.0], rotation=[0.0, 0.3826834, 0.0, 0.9238795])
    nodes.append({"name": "parent", "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0.5, 0, 1],
                  "children": [0]})
    b.gltf["scenes"][0]["nodes"] = [2]
    return b.to_bytes()


def points_and_lines() -> bytes:
    """A triangle quad, and the same vertices again as POINTS and as LINES."""
    b = GlbBuilder("rt feature_assets.py")
    material = b.add_material(pbr())
    quad(b, "surface", material)
    primitive = b.gltf["meshes"][0]["primitives"][0]
    b.gltf["meshes"][0]["primitives"] += [dict(primitive, mode=0), dict(primitive, mode=1)]
    return b.to_bytes()


def sparse() -> bytes:
    """A flat grid of which sparse substitution lifts two vertices."""
    b = GlbBuilder("rt feature_assets.py")
    quad(b, "lifted", b.add_material(pbr()))
    position = b.gltf["accessors"][b.gltf["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    indices = b._view(np.array([1, 2], "<u2").tobytes(), None)
    values = b._view(np.array([[1, -1, 0.5], [1, 1, 0.5]], "<f4").tobytes(), None)
    position["sparse"] = {"count": 2, "indices": {"bufferView": indices, "componentType": 5123},
                          "values": {"bufferView": values}}
    position["max"][2] = 0.5
    return b.to_bytes()


def no_buffer_view() -> bytes:
    """Positions whose z are all zero, from an accessor with no buffer view
    and sparse x and y."""
    b = GlbBuilder("rt feature_assets.py")
    quad(b, "from_sparse", b.add_material(pbr()))
    position = b.gltf["accessors"][b.gltf["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    indices = b._view(np.arange(4, dtype="<u1").tobytes(), None)
    values = b._view(QUAD_POSITIONS.astype("<f4").tobytes(), None)
    position.pop("bufferView")
    position["sparse"] = {"count": 4, "indices": {"bufferView": indices, "componentType": 5121},
                          "values": {"bufferView": values}}
    return b.to_bytes()


def skinned() -> bytes:
    """A quad bound to one joint: drawn in its bind pose."""
    b = GlbBuilder("rt feature_assets.py")
    joints = np.zeros((4, 4), np.float32)
    weights = np.tile(np.array([1, 0, 0, 0], np.float32), (4, 1))
    quad(b, "skinned", b.add_material(pbr()), JOINTS_0=joints, WEIGHTS_0=weights)
    attributes = b.gltf["meshes"][0]["primitives"][0]["attributes"]
    joint_accessor = b.gltf["accessors"][attributes["JOINTS_0"]]
    b.gltf["bufferViews"][joint_accessor["bufferView"]]["byteLength"] = 16
    joint_accessor["componentType"] = 5121  # JOINTS_0 as unsigned bytes, all joint 0
    b.gltf["nodes"].append({"name": "joint"})
    b.gltf["skins"] = [{"joints": [1]}]
    b.gltf["nodes"][0]["skin"] = 0
    return b.to_bytes()


def morph_targets() -> bytes:
    b = GlbBuilder("rt feature_assets.py")
    quad(b, "morphing", b.add_material(pbr()))
    mesh = b.gltf["meshes"][0]
    offset = np.tile(np.array([0, 0, 0.5], np.float32), (4, 1))
    mesh["primitives"][0]["targets"] = [{"POSITION": b._accessor(offset, "VEC3", 5126, 34962, True)}]
    mesh["weights"] = [0.5]
    return b.to_bytes()


def animation() -> bytes:
    """A quad that slides along x while the shutter is open."""
    b = GlbBuilder("rt feature_assets.py")
    quad(b, "sliding", b.add_material(pbr((0.8, 0.2, 0.2, 1.0))))
    times = b._accessor(np.array([[0.0], [1.0]], "<f4"), "SCALAR", 5126, None, True)
    moves = b._accessor(np.array([[0, 0, 0], [0.5, 0, 0]], "<f4"), "VEC3", 5126, None)
    b.gltf["animations"] = [{"samplers": [{"input": times, "output": moves}],
                             "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]}]
    return b.to_bytes()


def orthographic_camera() -> bytes:
    b = GlbBuilder("rt feature_assets.py")
    quad(b, "card", b.add_material(pbr((0.2, 0.6, 0.3, 1.0))))
    b.gltf["cameras"] = [{"name": "top", "type": "orthographic",
                          "orthographic": {"xmag": 1.5, "ymag": 1.5, "znear": 0.1, "zfar": 20.0}}]
    b._node({"name": "top", "camera": 0, "translation": [0.0, 0.0, 5.0]})
    return b.to_bytes()
