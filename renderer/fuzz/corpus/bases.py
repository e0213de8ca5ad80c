"""The valid files every hostile case starts from, and the companions they name.

Each case breaks exactly one thing in one of these bases, so the bases stay
small, valid and shared: the loader must accept them untouched (the *_valid*
rows), and the fuzz targets' folder (renderer/fuzz/fuzz_folder.h) writes the
same companion bytes, so a seed naming buffer.bin or image.png finds the same
file under the fuzzer as in the corpus.
"""

from __future__ import annotations

import base64
import copy
import json
import struct

# --- The companion files (fuzz_folder.h writes the same bytes) -----------------

FLOATS = [0, 0, 0, 1, 0, 0, 0, 1, 0] + [0, 0, 1] * 3
TRIANGLE_BIN = struct.pack("<18f", *FLOATS) + struct.pack("<3I", 0, 1, 2)  # 84 bytes
PNG = bytes.fromhex(
    "89504e470d0a1a0a0000000d4948445200000002000000020802000000fdd49a"
    "73000000124944415478da63f8cfc0c000c20cff8100001fee05fbf1abba7700"
    "00000049454e44ae426082")


def png_header(width: int, height: int) -> bytes:
    """A PNG signature and IHDR claiming width x height, and nothing after."""
    return (b"\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR" + struct.pack(">II", width, height)
            + bytes([8, 2, 0, 0, 0, 0, 0, 0, 0]))


def data_uri(payload: bytes, media: str = "application/octet-stream") -> str:
    return f"data:{media};base64," + base64.b64encode(payload).decode()


# --- Valid bases, each case breaks one thing ----------------------------------

def triangle_doc(uri: str | None = None) -> dict:
    """One indexed triangle with normals; its buffer at `uri` (data: URI by default)."""
    buffer = {"byteLength": len(TRIANGLE_BIN)}
    buffer["uri"] = data_uri(TRIANGLE_BIN) if uri is None else uri
    return {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "buffers": [buffer],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 72, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5125, "count": 3, "type": "SCALAR"}],
    }


def with_buffer(doc: dict, payload: bytes) -> dict:
    doc["buffers"] = [{"byteLength": len(payload), "uri": data_uri(payload)}]
    return doc


def textured_doc(image: dict) -> dict:
    """The triangle with texture coordinates and a material whose base colour is `image`."""
    payload = TRIANGLE_BIN + struct.pack("<6f", 0, 0, 1, 0, 0, 1)
    doc = with_buffer(triangle_doc(), payload)
    doc["bufferViews"].append({"buffer": 0, "byteOffset": 84, "byteLength": 24})
    doc["accessors"].append({"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC2"})
    doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 3
    doc["meshes"][0]["primitives"][0]["material"] = 0
    doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
    doc["textures"] = [{"source": 0}]
    doc["images"] = [image]
    return doc


def dump(doc: dict) -> bytes:
    return json.dumps(doc, allow_nan=True).encode()


def glb(doc: dict, bin_chunk: bytes | None) -> bytes:
    """`doc` as a GLB; its first buffer (no uri) is `bin_chunk`."""
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text
    if bin_chunk is not None:
        padded = bin_chunk + b"\0" * (-len(bin_chunk) % 4)
        body += struct.pack("<II", len(padded), 0x004E4942) + padded
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


def glb_doc() -> dict:
    doc = triangle_doc()
    doc["buffers"] = [{"byteLength": len(TRIANGLE_BIN)}]
    return doc


OBJ = b"""# one quad, two objects
mtllib base.mtl
o first
usemtl textured
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
f 1/1/1 2/2/1 3/3/1 4/4/1
o second
usemtl plain
v 0 0 1
v 1 0 1
v 0 1 1
f 5 6 7
"""
MTL = b"""newmtl textured
Kd 0.8 0.8 0.8
Ks 0.1 0.1 0.1
Ns 20
map_Kd image.png
newmtl plain
Kd 0.5 0.2 0.2
illum 3
"""


def obj(*lines: str, mtllib: str | None = "base.mtl") -> bytes:
    head = f"mtllib {mtllib}\n" if mtllib is not None else ""
    return (head + "".join(line + "\n" for line in lines)).encode()


TRI = ("v 0 0 0", "v 1 0 0", "v 0 1 0")


class Corpus:
    """The files in memory: (name, bytes) and a manifest row per scene file."""

    def __init__(self) -> None:
        self.files: dict[str, bytes] = {}
        self.rows: list[tuple[str, str, str]] = []

    def add(self, name: str, data: bytes, expect: str = "error", mentions: str = "") -> None:
        assert name not in self.files, name
        assert expect in ("error", "loads", "any") and "\t" not in mentions
        self.files[name] = data
        self.rows.append((name, expect, mentions))

    def companion(self, name: str, data: bytes) -> None:
        assert name not in self.files, name
        self.files[name] = data


def truncations(size: int, count: int) -> list[int]:
    """About `count` lengths in [0, size): all the small ones, then spread out."""
    lengths = set(range(min(size, 24)))
    step = max(1, size // count)
    lengths.update(range(0, size, step))
    lengths.update({size - 1, size - 2, size // 2})
    return sorted(n for n in lengths if 0 <= n < size)


def gltf_case(c: Corpus):
    """`case(name, mutate, ...)`: adds gltf_<name>.gltf, a copy of `doc` (the triangle by default) after `mutate`."""
    def case(name: str, mutate, expect: str = "error", mentions: str = "", doc: dict | None = None) -> None:
        d = copy.deepcopy(doc if doc is not None else triangle_doc())
        mutate(d)
        c.add(f"gltf_{name}.gltf", dump(d), expect, mentions)
    return case


def accessor(i: int, **fields):
    return lambda d: d["accessors"][i].update(fields)


def view(i: int, **fields):
    return lambda d: d["bufferViews"][i].update(fields)
