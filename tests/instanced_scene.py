"""A glTF scene whose nodes share one mesh (an octahedron, 8 triangles), for
the rtcore and API instancing tests; `copies` gives each node its own copy of
the mesh instead, which the loader flattens into world space. `moving` nodes
(by number) slide and turn while the shutter is open (asset.extras.rt.motions),
the nodes named "n<k>"."""
import base64
import json
import math
import struct


def instanced_gltf(nodes: int = 30, copies: bool = False, moving: tuple[int, ...] = ()) -> str:
    positions = [1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1]
    indices = [0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5]
    data = struct.pack(f"<{len(positions)}f", *positions) + struct.pack(f"<{len(indices)}I", *indices)
    mesh = {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}
    placed = []
    for k in range(nodes):
        angle = 0.3 * k
        placed.append({"name": f"n{k}", "mesh": k if copies else 0,
                       "translation": [2.5 * (k % 6) - 6, 0.8, -2.5 * (k // 6)],
                       "rotation": [0, math.sin(angle / 2), 0, math.cos(angle / 2)],
                       "scale": [0.8, 0.8 + 0.05 * k, -0.8 if k % 7 == 3 else 0.8]})
    motions = [{"node": f"n{k}", "translation": [2.5 * (k % 6) - 5.4, 1.0, -2.5 * (k // 6) + 0.3],
                "rotation": [0, math.sin(0.3 * k / 2 + 0.2), 0, math.cos(0.3 * k / 2 + 0.2)]} for k in moving]
    doc = {
        "asset": {"version": "2.0", **({"extras": {"rt": {"motions": motions}}} if motions else {})},
        "scene": 0,
        "scenes": [{"nodes": list(range(nodes))}],
        "nodes": placed,
        "meshes": [mesh] * (nodes if copies else 1),
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 4 * len(positions)},
                        {"buffer": 0, "byteOffset": 4 * len(positions), "byteLength": 4 * len(indices)}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
             "min": [-1, -1, -1], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5125, "count": len(indices), "type": "SCALAR"},
        ],
    }
    return json.dumps(doc)
