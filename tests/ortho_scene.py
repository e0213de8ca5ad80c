"""A glTF scene with an orthographic camera, for the CLI, rtcore and API tests.

A unit square in the z = 0 plane (x and y from -0.5 to 0.5) lit by a point
light, seen by an orthographic camera "plan" on +z and a perspective camera
"eye": with ymag m the square is 1 / (2 m) of the image's height.
"""
import base64
import json
import struct


def ortho_gltf(ymag: float = 1.0, distance: float = 5.0, xmag: float | None = None) -> str:
    positions = [-0.5, -0.5, 0, 0.5, -0.5, 0, 0.5, 0.5, 0, -0.5, 0.5, 0]
    indices = [0, 1, 2, 0, 2, 3]
    data = struct.pack("<12f", *positions) + struct.pack("<6I", *indices)
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 200}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"mesh": 0},
            {"camera": 0, "translation": [0, 0, distance]},
            {"camera": 1, "translation": [0, 0, distance]},
            {"translation": [0, 0, 3], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        ],
        "cameras": [
            {"type": "orthographic", "name": "plan",
             "orthographic": {"xmag": ymag if xmag is None else xmag, "ymag": ymag, "znear": 0, "zfar": 100}},
            {"type": "perspective", "name": "eye", "perspective": {"yfov": 0.6, "znear": 0.1}},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 24}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 0]},
            {"bufferView": 1, "componentType": 5125, "count": 6, "type": "SCALAR"},
        ],
    }
    return json.dumps(doc)


def bright_box(image, threshold: float = 0.05):
    """(x0, y0, x1, y1) of the pixels brighter than `threshold` (any channel), inclusive; None if none."""
    import numpy as np
    mask = np.asarray(image).max(axis=-1) > threshold
    ys, xs = np.nonzero(mask)
    if len(xs) == 0:
        return None
    return int(xs.min()), int(ys.min()), int(xs.max()), int(ys.max())
