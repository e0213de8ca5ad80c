"""Writing and checking binary glTF 2.0 (.glb) files.

GlbBuilder collects triangle meshes (with any extra vertex attributes),
metallic-roughness materials, images and textures, KHR_lights_punctual point
lights and perspective cameras into a single buffer;
validate_glb() re-reads the bytes and checks the structure the way a strict
loader would (chunk layout, view and accessor bounds, POSITION min/max, index
range), so a broken sample fails here rather than in the renderer.
"""

from __future__ import annotations

import json
import struct

import numpy as np

GLB_MAGIC, GLB_VERSION = b"glTF", 2
CHUNK_JSON, CHUNK_BIN = 0x4E4F534A, 0x004E4942
FLOAT, UINT32 = 5126, 5125
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
LIGHTS_EXT = "KHR_lights_punctual"
_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
_COMPONENT_DTYPES = {5120: "i1", 5121: "u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}


class GlbError(ValueError):
    pass


def look_at_quaternion(eye, target, up=(0.0, 1.0, 0.0)) -> list[float]:
    """Rotation (x, y, z, w) that turns a glTF camera (looking down -Z, +Y up)
    at `eye` towards `target`."""
    back = np.asarray(eye, float) - np.asarray(target, float)
    back /= np.linalg.norm(back)
    right = np.cross(up, back)
    right /= np.linalg.norm(right)
    true_up = np.cross(back, right)
    m = np.stack([right, true_up, back], axis=1)  # columns: local axes in world space
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0:
        s = 2.0 * np.sqrt(trace + 1.0)
        q = [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, s / 4]
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * np.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = [s / 4, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s, (m[2, 1] - m[1, 2]) / s]
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * np.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = [(m[0, 1] + m[1, 0]) / s, s / 4, (m[1, 2] + m[2, 1]) / s, (m[0, 2] - m[2, 0]) / s]
    else:
        s = 2.0 * np.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = [(m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, s / 4, (m[1, 0] - m[0, 1]) / s]
    q = np.asarray(q) / np.linalg.norm(q)
    return [round(float(c), 7) for c in q]


class GlbBuilder:
    def __init__(self, generator: str = "rt make_samples.py"):
        self.gltf: dict = {
            "asset": {"version": "2.0", "generator": generator},
            "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [],
            "materials": [], "accessors": [], "bufferViews": [], "buffers": [],
        }
        self.bin = bytearray()

    def _view(self, data: bytes, target: int | None) -> int:
        """A buffer view of `data`; `target` None for one that is no vertex or
        index buffer (images, sparse parts, animation keys)."""
        self.bin.extend(b"\0" * (-len(self.bin) % 4))
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if target is not None:
            view["target"] = target
        self.gltf["bufferViews"].append(view)
        self.bin.extend(data)
        return len(self.gltf["bufferViews"]) - 1

    def _accessor(self, array: np.ndarray, kind: str, component: int, target: int | None,
                  bounds: bool = False) -> int:
        accessor = {"bufferView": self._view(array.tobytes(), target), "componentType": component,
                    "count": int(array.shape[0]), "type": kind}
        if bounds:
            accessor["min"] = [float(v) for v in array.min(axis=0)]
            accessor["max"] = [float(v) for v in array.max(axis=0)]
        self.gltf["accessors"].append(accessor)
        return len(self.gltf["accessors"]) - 1

    def _node(self, node: dict) -> int:
        self.gltf["nodes"].append(node)
        index = len(self.gltf["nodes"]) - 1
        self.gltf["scenes"][0]["nodes"].append(index)
        return index

    def material(self, name: str, base_color, metallic: float, roughness: float) -> int:
        self.gltf["materials"].append({"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": [float(c) for c in base_color] + [1.0],
            "metallicFactor": float(metallic), "roughnessFactor": float(roughness)}})
        return len(self.gltf["materials"]) - 1

    def add_material(self, material: dict) -> int:
        """Any glTF material object, as given."""
        self.gltf["materials"].append(material)
        return len(self.gltf["materials"]) - 1

    def image(self, data: bytes, mime_type: str = "image/png") -> int:
        """An encoded image stored in the buffer."""
        self.gltf.setdefault("images", []).append(
            {"bufferView": self._view(data, None), "mimeType": mime_type})
        return len(self.gltf["images"]) - 1

    def texture(self, image: int, sampler: dict | None = None) -> int:
        texture = {"source": image}
        if sampler is not None:
            self.gltf.setdefault("samplers", []).append(sampler)
            texture["sampler"] = len(self.gltf["samplers"]) - 1
        self.gltf.setdefault("textures", []).append(texture)
        return len(self.gltf["textures"]) - 1

    def use_extension(self, name: str, required: bool = False) -> None:
        for key in ("extensionsUsed",) + (("extensionsRequired",) if required else ()):
            listed = self.gltf.setdefault(key, [])
            if name not in listed:
                listed.append(name)

    def mesh(self, name: str, positions, triangles, material: int, normals=None,
             attributes: dict | None = None) -> int:
        """A one-primitive mesh on its own root node. `attributes` maps further
        semantics (TEXCOORD_0, COLOR_0, TANGENT...) to float arrays."""
        positions = np.ascontiguousarray(positions, dtype="<f4")
        indices = np.ascontiguousarray(triangles, dtype="<u4").reshape(-1)
        extra = dict(attributes or {})
        if normals is not None:
            extra = {"NORMAL": normals, **extra}
        attributes = {"POSITION": self._accessor(positions, "VEC3", FLOAT, ARRAY_BUFFER, True)}
        for semantic, values in extra.items():
            values = np.ascontiguousarray(values, dtype="<f4")
            kind = {2: "VEC2", 3: "VEC3", 4: "VEC4"}[values.shape[1]]
            attributes[semantic] = self._accessor(values, kind, FLOAT, ARRAY_BUFFER)
        primitive = {"attributes": attributes, "material": material, "mode": 4,
                     "indices": self._accessor(indices, "SCALAR", UINT32, ELEMENT_ARRAY_BUFFER)}
        self.gltf["meshes"].append({"name": name, "primitives": [primitive]})
        return self._node({"name": name, "mesh": len(self.gltf["meshes"]) - 1})

    def point_light(self, name: str, position, intensity: float, color=(1.0, 1.0, 1.0)) -> int:
        ext = self.gltf.setdefault("extensions", {}).setdefault(LIGHTS_EXT, {"lights": []})
        ext["lights"].append({"name": name, "type": "point", "color": [float(c) for c in color],
                              "intensity": float(intensity)})
        used = self.gltf.setdefault("extensionsUsed", [])
        if LIGHTS_EXT not in used:
            used.append(LIGHTS_EXT)
        return self._node({"name": name, "translation": [float(c) for c in position],
                           "extensions": {LIGHTS_EXT: {"light": len(ext["lights"]) - 1}}})

    def camera(self, name: str, eye, target, yfov: float, aspect: float,
               znear: float, zfar: float | None = None) -> int:
        perspective = {"aspectRatio": aspect, "yfov": yfov, "znear": znear}
        if zfar is not None:
            perspective["zfar"] = zfar
        self.gltf.setdefault("cameras", []).append(
            {"name": name, "type": "perspective", "perspective": perspective})
        return self._node({"name": name, "camera": len(self.gltf["cameras"]) - 1,
                           "translation": [float(c) for c in eye],
                           "rotation": look_at_quaternion(eye, target)})

    def to_bytes(self) -> bytes:
        self.bin.extend(b"\0" * (-len(self.bin) % 4))
        self.gltf["buffers"] = [{"byteLength": len(self.bin)}]
        text = json.dumps(self.gltf, separators=(",", ":")).encode()
        text += b" " * (-len(text) % 4)
        total = 12 + 8 + len(text) + 8 + len(self.bin)
        return b"".join([
            struct.pack("<4sII", GLB_MAGIC, GLB_VERSION, total),
            struct.pack("<II", len(text), CHUNK_JSON), text,
            struct.pack("<II", len(self.bin), CHUNK_BIN), bytes(self.bin)])


def with_json(data: bytes, edit) -> bytes:
    """The GLB `data` with `edit(doc)` applied to its JSON chunk, the BIN chunk
    kept as it is (benchmarks and tests make variants of one file this way)."""
    length, _ = struct.unpack_from("<II", data, 12)
    doc = json.loads(data[20:20 + length])
    edit(doc)
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    rest = data[20 + length:]
    return b"".join([struct.pack("<4sII", GLB_MAGIC, GLB_VERSION, 20 + len(text) + len(rest)),
                     struct.pack("<II", len(text), CHUNK_JSON), text, rest])


def _check(condition: bool, message: str) -> None:
    if not condition:
        raise GlbError(message)


def _read_accessor(gltf: dict, binary: bytes, index: int) -> np.ndarray:
    _check(0 <= index < len(gltf["accessors"]), f"accessor {index} does not exist")
    acc = gltf["accessors"][index]
    dtype = _COMPONENT_DTYPES.get(acc.get("componentType"))
    width = _COMPONENTS.get(acc.get("type"))
    _check(dtype is not None and width is not None, f"accessor {index}: bad type")
    view = gltf["bufferViews"][acc["bufferView"]]
    element = np.dtype(dtype).itemsize * width
    stride = view.get("byteStride", element)
    offset = acc.get("byteOffset", 0)
    count = acc["count"]
    _check(count > 0 and offset % np.dtype(dtype).itemsize == 0, f"accessor {index}: bad offset/count")
    _check(offset + stride * (count - 1) + element <= view["byteLength"],
           f"accessor {index}: runs past its bufferView")
    start = view.get("byteOffset", 0) + offset
    _check(start % 4 == 0, f"accessor {index}: not 4-byte aligned")
    if stride == element:
        data = np.frombuffer(binary, dtype, count * width, start)
    else:
        rows = [np.frombuffer(binary, dtype, width, start + i * stride) for i in range(count)]
        data = np.concatenate(rows)
    return data.reshape(count, width) if width > 1 else data


def validate_glb(data: bytes) -> dict:
    """Check a GLB's structure; returns {'triangles', 'vertices', 'lights', 'cameras'}."""
    _check(len(data) >= 28, "file too short")
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    _check(magic == GLB_MAGIC and version == GLB_VERSION, "bad magic or version")
    _check(length == len(data), f"header length {length} != file size {len(data)}")
    json_len, json_type = struct.unpack_from("<II", data, 12)
    _check(json_type == CHUNK_JSON and json_len % 4 == 0, "first chunk is not padded JSON")
    gltf = json.loads(data[20:20 + json_len])
    bin_at = 20 + json_len
    bin_len, bin_type = struct.unpack_from("<II", data, bin_at)
    _check(bin_type == CHUNK_BIN and bin_len % 4 == 0, "second chunk is not padded BIN")
    _check(bin_at + 8 + bin_len == len(data), "chunks do not fill the file")
    binary = data[bin_at + 8:]
    _check(len(gltf.get("buffers", [])) == 1 and gltf["buffers"][0]["byteLength"] <= bin_len,
           "buffer 0 must fit in the BIN chunk")
    for i, view in enumerate(gltf["bufferViews"]):
        _check(view["buffer"] == 0 and view.get("byteOffset", 0) + view["byteLength"]
               <= gltf["buffers"][0]["byteLength"], f"bufferView {i} runs past the buffer")
    triangles = vertices = 0
    for m, mesh in enumerate(gltf["meshes"]):
        for primitive in mesh["primitives"]:
            _check(primitive.get("mode", 4) == 4, f"mesh {m}: not a triangle list")
            _check(0 <= primitive.get("material", 0) < len(gltf.get("materials", [])),
                   f"mesh {m}: bad material")
            attrs = primitive["attributes"]
            position = _read_accessor(gltf, binary, attrs["POSITION"])
            acc = gltf["accessors"][attrs["POSITION"]]
            _check(acc["componentType"] == FLOAT and acc["type"] == "VEC3", f"mesh {m}: POSITION type")
            _check(np.all(np.isfinite(position)), f"mesh {m}: non-finite positions")
            _check(np.array_equal(np.asarray(acc["min"], "f4"), position.min(axis=0)) and
                   np.array_equal(np.asarray(acc["max"], "f4"), position.max(axis=0)),
                   f"mesh {m}: POSITION min/max do not match the data")
            if "NORMAL" in attrs:
                normal = _read_accessor(gltf, binary, attrs["NORMAL"])
                _check(normal.shape == position.shape, f"mesh {m}: NORMAL count != POSITION count")
                _check(np.allclose(np.linalg.norm(normal, axis=1), 1.0, atol=1e-3),
                       f"mesh {m}: normals are not unit length")
            indices = _read_accessor(gltf, binary, primitive["indices"])
            _check(gltf["accessors"][primitive["indices"]]["componentType"] == UINT32,
                   f"mesh {m}: indices are not uint32")
            _check(indices.size % 3 == 0, f"mesh {m}: index count not a multiple of 3")
            _check(int(indices.max()) < len(position), f"mesh {m}: index out of range")
            triangles += indices.size // 3
            vertices += len(position)
    lights = gltf.get("extensions", {}).get(LIGHTS_EXT, {}).get("lights", [])
    _check(not lights or LIGHTS_EXT in gltf.get("extensionsUsed", []),
           f"{LIGHTS_EXT} used but not listed in extensionsUsed")
    for i, node in enumerate(gltf["nodes"]):
        _check(node.get("mesh", 0) < len(gltf["meshes"]), f"node {i}: bad mesh")
        _check(node.get("camera", 0) < len(gltf.get("cameras", [])) or "camera" not in node,
               f"node {i}: bad camera")
        light = node.get("extensions", {}).get(LIGHTS_EXT, {}).get("light")
        _check(light is None or 0 <= light < len(lights), f"node {i}: bad light")
    for n in gltf["scenes"][gltf.get("scene", 0)]["nodes"]:
        _check(0 <= n < len(gltf["nodes"]), f"scene node {n} does not exist")
    return {"triangles": triangles, "vertices": vertices, "lights": len(lights),
            "cameras": len(gltf.get("cameras", []))}
