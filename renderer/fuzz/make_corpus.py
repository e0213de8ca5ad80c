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
import base64
import copy
import hashlib
import json
import math
import os
import shutil
import struct
import sys
from pathlib import Path

MTL_SEPARATOR = b"\n#%mtl\n"  # fuzz_obj.cpp: OBJ text, then fuzz.mtl's

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


# --- glTF (JSON) ----------------------------------------------------------------

def gltf_cases(c: Corpus) -> None:
    def case(name: str, mutate, expect: str = "error", mentions: str = "", doc: dict | None = None) -> None:
        d = copy.deepcopy(doc if doc is not None else triangle_doc())
        mutate(d)
        c.add(f"gltf_{name}.gltf", dump(d), expect, mentions)

    def accessor(i: int, **fields):
        return lambda d: d["accessors"][i].update(fields)

    def view(i: int, **fields):
        return lambda d: d["bufferViews"][i].update(fields)

    # Valid bases: the fuzzers' seeds too.
    c.add("gltf_valid.gltf", dump(triangle_doc()), "loads", "no lights")
    c.add("gltf_valid_external.gltf", dump(triangle_doc("buffer.bin")), "loads")
    c.add("gltf_valid_subfolder.gltf", dump(triangle_doc("sub/buffer.bin")), "loads")
    c.add("gltf_valid_textured.gltf", dump(textured_doc({"uri": "image.png"})), "loads")

    # Truncated text.
    text = dump(triangle_doc("buffer.bin"))
    for n in truncations(len(text), 48):
        c.add(f"gltf_truncated_{n:04d}.gltf", text[:n], "error", "" if n else "invalid JSON")

    # Not a glTF document at all.
    for name, raw, mentions in [
        ("empty", b"", "invalid JSON"), ("array", b"[]", "not a JSON object"),
        ("string", b'"glTF"', "not a JSON object"), ("number", b"2.0", "not a JSON object"),
        ("null", b"null", "not a JSON object"), ("nan_literal", b'{"asset": NaN}', "invalid JSON"),
        ("infinity_literal", b'{"asset": {"version": Infinity}}', "invalid JSON"),
        ("binary", bytes(range(256)) * 4, "invalid JSON"),
        ("nul_inside", text[:40] + b"\0" + text[40:], "invalid JSON"),
        ("bad_utf8", text.replace(b'"2.0"', b'"2.0\xff\xfe"'), "invalid JSON"),
        # nlohmann quotes the whole string it read last: here 200 KB and a stray byte.
        ("bad_utf8_long_string", text.replace(b'"2.0"', b'"' + b"A" * 200000 + b'\xff"'), "invalid JSON"),
        ("no_asset", b'{"scenes": []}', "asset"),
        ("number_overflow", text.replace(b'"count": 3', b'"count": 1e400', 1), "invalid JSON"),
        ("trailing_garbage", text + b"}}}", "invalid JSON"),
    ]:
        c.add(f"gltf_{name}.gltf", raw, "error", mentions)

    # Deep nesting, in the JSON and in the node graph.
    deep = b"[" * 100000 + b"]" * 100000
    c.add("gltf_deep_extras.gltf", text[:-1] + b', "extras": ' + deep + b"}", "error", "JSON nesting is deeper")
    c.add("gltf_deep_unclosed.gltf", b'{"extras": ' + b"{\"a\":" * 50000, "error", "JSON nesting is deeper")
    c.add("gltf_deep_strings.gltf", text[:-1] + b', "extras": "' + b"[{" * 50000 + b'"}', "loads")

    def chain(d: dict, length: int, scale: float | None = None) -> None:
        d["nodes"] = [{"children": [i + 1]} for i in range(length - 1)] + [{"mesh": 0}]
        if scale is not None:
            for node in d["nodes"]:
                node["scale"] = [scale] * 3
    case("deep_node_chain", lambda d: chain(d, 20000), "loads")
    case("deep_node_chain_overflowing", lambda d: chain(d, 2000, 2.0), "error", "world transform is not finite")
    case("node_cycle", lambda d: d["nodes"].extend([{"children": [2]}, {"children": [1]}])
         or d["scenes"][0]["nodes"].append(1), "error", "is reached twice")
    case("node_self_child", lambda d: d["nodes"][0].update(children=[0]), "error", "nodes[0] is reached twice")
    case("node_two_parents", lambda d: d["nodes"].extend([{"children": [0]}]) or d["scenes"][0]["nodes"].append(1),
         "error", "is reached twice")
    case("root_listed_twice", lambda d: d["scenes"][0].update(nodes=[0, 0]), "error", "is reached twice")
    for child in (-1, 1, 2**31 - 1, 2**31, 2**63):
        case(f"child_{child}", lambda d, ch=child: d["nodes"][0].update(children=[ch]), "error", "")
    case("scene_node_missing", lambda d: d["scenes"][0].update(nodes=[7]), "error", "refers to node 7")
    case("scene_missing", lambda d: d.update(scene=4), "error", "scene 4")
    case("scene_negative", lambda d: d.update(scene=-3), "error", "scene -3 does not exist")
    case("mesh_missing", lambda d: d["nodes"][0].update(mesh=9), "error", "refers to mesh 9")
    case("mesh_negative", lambda d: d["nodes"][0].update(mesh=-5), "error", "")
    case("camera_missing", lambda d: d["nodes"][0].update(camera=0), "error", "refers to camera 0")
    def no_scenes_cycle(d: dict) -> None:
        del d["scene"], d["scenes"]
        d["nodes"] += [{"children": [2]}, {"children": [1]}]
    case("no_scenes_cycle", no_scenes_cycle, "loads")  # the cycle hangs from no root: never reached

    # Accessors: huge counts and offsets, wrong types.
    for i, label in ((0, "positions"), (2, "indices")):
        for count in (4, 2**31 - 1, 2**32 - 1, 2**32, 2**62, 2**64 - 1):
            case(f"{label}_count_{count}", accessor(i, count=count), "error", "reach past the end")
        for offset in (4, 2**31, 2**64 - 1):
            case(f"{label}_offset_{offset}", accessor(i, byteOffset=offset), "error", "")
        case(f"{label}_count_negative", accessor(i, count=-1), "error", "")
        case(f"{label}_count_float", accessor(i, count=3.5), "error", "")
        case(f"{label}_count_2pow64", accessor(i, count=2**64), "error", "")
        case(f"{label}_count_string", accessor(i, count="3"), "error", "")
        case(f"{label}_no_view", lambda d, i=i: d["accessors"][i].pop("bufferView"), "error", "bufferView")
        case(f"{label}_view_missing", accessor(i, bufferView=99), "error", "")
    case("accessor_missing", lambda d: d["meshes"][0]["primitives"][0]["attributes"].update(NORMAL=40), "error",
         "refers to accessor 40")
    case("accessor_negative", lambda d: d["meshes"][0]["primitives"][0].update(indices=-7), "error", "")
    case("positions_short", accessor(0, componentType=5122), "error", "unsupported component type SHORT")
    case("positions_bad_component", accessor(0, componentType=1), "error", "")
    case("positions_vec4", accessor(0, type="VEC4"), "error", "has type VEC4")
    case("positions_bad_type", accessor(0, type="VEC9"), "error", "")
    case("indices_float", accessor(2, componentType=5126), "error", "unsupported component type FLOAT")
    case("indices_count_not_triangles", accessor(2, count=2), "error", "not a multiple of 3")
    case("sparse", accessor(0, sparse={"count": 1, "indices": {"bufferView": 2, "componentType": 5125},
                                       "values": {"bufferView": 0}}), "error", "is sparse")
    case("sparse_huge", accessor(0, sparse={"count": 2**32 - 1, "indices": {"bufferView": 2, "componentType": 5125,
                                            "byteOffset": 2**40}, "values": {"bufferView": 0}}), "error", "")
    for stride in (1, 4, 253, 2**31, 2**64 - 1):
        case(f"stride_{stride}", view(0, byteStride=stride), "error", "")
    for length in (0, 49, 2**31, 2**64 - 1):
        case(f"view_length_{length}", view(1, byteLength=length), "error", "")
    for offset in (80, 2**32, 2**64 - 1):
        case(f"view_offset_{offset}", view(1, byteOffset=offset), "error", "")
    case("view_buffer_missing", view(0, buffer=3), "error", "")
    case("view_buffer_negative", view(0, buffer=-1), "error", "")

    # Buffers: lengths that lie, and malformed data: URIs.
    for length in (0, 83, 85, 2**31, 2**32 + 84, 2**64 - 1):
        case(f"buffer_length_{length}", lambda d, n=length: d["buffers"][0].update(byteLength=n), "error", "")
        case(f"external_buffer_length_{length}", lambda d, n=length: d["buffers"][0].update(byteLength=n),
             "error", "", doc=triangle_doc("buffer.bin"))
    case("buffer_length_negative", lambda d: d["buffers"][0].update(byteLength=-84), "error", "")
    case("buffer_no_length", lambda d: d["buffers"][0].pop("byteLength"), "error", "")
    case("buffer_no_uri", lambda d: d["buffers"][0].pop("uri"), "error", "buffers[0] has no uri")
    b64 = base64.b64encode(TRIANGLE_BIN).decode()
    for name, uri, mentions in [
        ("short", "data:application/octet-stream;base64," + b64[:-8], "declares byteLength 84"),
        ("junk", "data:application/octet-stream;base64," + b64[:40] + "!!!!" + b64[44:], "declares byteLength"),
        ("padding", "data:application/octet-stream;base64,====" + b64, "declares byteLength"),
        ("empty_payload", "data:application/octet-stream;base64,", "declares byteLength"),
        ("not_base64", "data:application/octet-stream," + "A" * 112, "data: URI of a kind we cannot decode"),
        ("no_media_type", "data:;base64," + b64, "data: URI"),
        ("text_media_type", "data:text/plain;base64," + b64, "any"),  # one of tinygltf's media types
        ("no_comma", "data:application/octet-stream;base64", "data: URI"),
        ("bare", "data:", "data: URI"),
        ("gltf_buffer", "data:application/gltf-buffer;base64," + b64 + "====", "any"),
    ]:
        case(f"data_uri_{name}", lambda d, u=uri: d["buffers"][0].update(uri=u),
             "any" if mentions == "any" else "error", "" if mentions == "any" else mentions)

    # References out of the folder, for buffers and images alike.
    escapes = [
        ("parent", "../outside.bin", "leads outside the scene folder"),
        ("parent_encoded", "%2e%2e/outside.bin", "leads outside the scene folder"),
        ("parent_encoded_slash", "..%2foutside.bin", "leads outside the scene folder"),
        ("subfolder_parent", "sub/../../outside.bin", "leads outside the scene folder"),
        ("symlink", "escape/outside.bin", "leads outside the scene folder"),
        ("symlink_twice", "escape/escape/outside.bin", ""),
        ("absolute", "/etc/passwd", "absolute path"),
        ("absolute_encoded", "%2fetc%2fpasswd", "absolute path"),
        ("absolute_outside", "//outside.bin", "absolute path"),
        ("url", "http://example.com/buffer.bin", "is a URL"),
        ("file_url", "file:///etc/passwd", "is a URL"),
        ("empty", "", "is empty"),
        ("nul", "buffer.bin\u0000.png", "NUL"),
        ("nul_encoded", "buffer.bin%00.png", "NUL"),
        ("folder", "folder.bin", ""),
        ("current_folder", ".", ""),
        ("missing", "missing.bin", "missing.bin"),
        ("long", "a/" * 3000 + "buffer.bin", ""),
        ("backslash", "..\\outside.bin", ""),
        ("proc", "../../../../../../../../proc/self/environ", "leads outside the scene folder"),
    ]
    for name, uri, mentions in escapes:
        case(f"buffer_uri_{name}", lambda d, u=uri: d["buffers"][0].update(uri=u), "error", mentions,
             doc=triangle_doc("buffer.bin"))
        # A missing image is only a warning; on POSIX a backslash is part of a file name.
        case(f"image_uri_{name}", lambda d: None, "any" if name in ("missing", "backslash") else "error",
             mentions, doc=textured_doc({"uri": uri}))
    case("buffer_uri_symlink_back_inside", lambda d: None, "loads", doc=triangle_doc("escape/scenes/buffer.bin"))
    case("buffer_uri_dot_slash", lambda d: None, "loads", doc=triangle_doc("./buffer.bin"))
    case("image_uri_dot_slash", lambda d: None, "loads", doc=textured_doc({"uri": "./image.png"}))
    case("buffer_uri_not_string", lambda d: d["buffers"][0].update(uri=42), "error", "buffers[0].uri is not a string")
    case("image_uri_not_string", lambda d: None, "error", "images[0].uri is not a string",
         doc=textured_doc({"uri": []}))

    # Images: malformed data: URIs, lying headers, views out of their buffer.
    for name, image, expect, mentions in [
        ("data_uri_junk", {"uri": "data:image/png;base64,!!!!"}, "any", ""),
        ("data_uri_empty", {"uri": "data:image/png;base64,"}, "any", ""),
        ("data_uri_unknown_kind", {"uri": "data:image/webp;base64,AAAA"}, "error", "data: URI"),
        ("data_uri_plain", {"uri": "data:image/png,rawbytes"}, "error", "data: URI"),
        ("not_an_image", {"uri": "buffer.bin"}, "loads", "is not a PNG, JPEG, BMP, TGA or WebP image"),
        # 768 MiB of 8-bit texels and mips: an RGB image of 14189x14189 fits, one texel more per side not.
        ("huge_header", {"uri": data_uri(png_header(16000, 16000), "image/png")}, "error", "texels"),
        ("huge_header_14190", {"uri": data_uri(png_header(14190, 14190), "image/png")}, "error", "texels"),
        ("huge_header_14189", {"uri": data_uri(png_header(14189, 14189), "image/png")}, "loads", "texture ignored"),
        # Beyond what stb_image decodes at all: a broken image, only a warning.
        ("huge_header_65536", {"uri": data_uri(png_header(65536, 65536), "image/png")}, "loads", "texture ignored"),
        ("huge_header_100000", {"uri": data_uri(png_header(100000, 100000), "image/png")}, "loads",
         "texture ignored"),
        ("zero_header", {"uri": data_uri(png_header(0, 0), "image/png")}, "loads", "texture ignored"),
        ("truncated_png", {"uri": data_uri(PNG[:40], "image/png")}, "loads", "texture ignored"),
        ("view_missing", {"bufferView": 9, "mimeType": "image/png"}, "error", "images[0].bufferView"),
        ("view_negative", {"bufferView": -1, "mimeType": "image/png"}, "any", ""),
        ("view_huge", {"bufferView": 2**64 - 1, "mimeType": "image/png"}, "error", "images[0].bufferView"),
        ("uri_and_view", {"bufferView": 0, "uri": "image.png"}, "any", ""),
        ("no_source", {}, "any", ""),
    ]:
        c.add(f"gltf_image_{name}.gltf", dump(textured_doc(image)), expect, mentions)
    for name, fields, mentions in [
        ("past_buffer", {"byteOffset": 100, "byteLength": 100}, "does not lie inside"),
        ("huge_length", {"byteOffset": 0, "byteLength": 2**64 - 1}, "does not lie inside"),
        ("empty", {"byteOffset": 0, "byteLength": 0}, "does not lie inside"),
    ]:
        d = textured_doc({"bufferView": 4, "mimeType": "image/png"})
        d["bufferViews"].append({"buffer": 0, **fields})
        c.add(f"gltf_image_view_{name}.gltf", dump(d), "error", mentions)
    for name, mutate, expect, mentions in [
        ("texture_missing", lambda d: d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"].update(index=5),
         "error", "refers to texture 5"),
        ("texture_negative", lambda d: d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"].update(
            index=-2), "any", ""),
        ("texcoord_9", lambda d: d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"].update(texCoord=9),
         "loads", "only TEXCOORD_0 and TEXCOORD_1 are read"),
        ("source_missing", lambda d: d["textures"][0].update(source=3), "error", "refers to image 3"),
        ("sampler_missing", lambda d: d["textures"][0].update(sampler=2), "error", "refers to sampler 2"),
        ("wrap_unknown", lambda d: d.update(samplers=[{"wrapS": 1}]) or d["textures"][0].update(sampler=0),
         "error", "unknown wrap mode 1"),
        ("texcoord_count", lambda d: d["accessors"][3].update(count=2), "error", "has 2 elements, but POSITION has 3"),
        ("texcoord_bytes", lambda d: d["accessors"][3].update(componentType=5121), "error", "not normalized"),
        ("material_missing", lambda d: d["meshes"][0]["primitives"][0].update(material=4), "error",
         "refers to material 4"),
        ("material_negative", lambda d: d["meshes"][0]["primitives"][0].update(material=-9), "error", ""),
        ("base_color_3", lambda d: d["materials"][0]["pbrMetallicRoughness"].update(baseColorFactor=[1, 1, 1]),
         "any", ""),  # tinygltf keeps its default for a factor of the wrong size
        ("base_color_huge", lambda d: d["materials"][0]["pbrMetallicRoughness"].update(
            baseColorFactor=[1e308, -1e308, 1, 1]), "loads", ""),
        ("metallic_string", lambda d: d["materials"][0]["pbrMetallicRoughness"].update(metallicFactor="1"),
         "any", ""),
        ("ior_zero", lambda d: d["materials"][0].update(extensions={"KHR_materials_ior": {"ior": 0}}),
         "error", "KHR_materials_ior.ior"),
        ("ior_huge", lambda d: d["materials"][0].update(extensions={"KHR_materials_ior": {"ior": 1e300}}),
         "error", "KHR_materials_ior.ior is 1e+300, expected"),
        ("ior_string", lambda d: d["materials"][0].update(extensions={"KHR_materials_ior": {"ior": "1.5"}}),
         "error", "KHR_materials_ior.ior"),
        ("transmission_string", lambda d: d["materials"][0].update(
            extensions={"KHR_materials_transmission": {"transmissionFactor": "0.5"}}), "error", "transmissionFactor"),
        ("extension_not_object", lambda d: d["materials"][0].update(extensions={"KHR_materials_ior": 3}), "any", ""),
    ]:
        d = textured_doc({"uri": "image.png"})
        mutate(d)
        c.add(f"gltf_material_{name}.gltf", dump(d), expect, mentions)

    # Numbers out of range in the node transforms, cameras and lights.
    for name, node, mentions in [
        ("scale_1e300", {"scale": [1e300, 1, 1]}, "not finite after the node transform"),
        ("scale_1e39", {"scale": [1e39, 1e39, 1e39]}, "not finite after the node transform"),
        ("translation_1e308", {"translation": [1e308, 0, 0]}, ""),
        ("translation_2", {"translation": [1, 2]}, "translation has 2 values"),
        ("rotation_zero", {"rotation": [0, 0, 0, 0]}, "rotation is not a rotation"),
        ("rotation_huge", {"rotation": [1e308, 1e308, 1e308, 1e308]}, ""),
        ("matrix_15", {"matrix": [1] * 15}, "matrix has 15 values"),
        ("matrix_huge", {"matrix": [1e308] * 16}, ""),
        ("matrix_singular", {"matrix": [0] * 16}, "any"),
        ("matrix_and_trs", {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], "scale": [1e300] * 3}, "any"),
        ("name_not_string", {"name": {"a": 1}}, "any"),
    ]:
        case(f"node_{name}", lambda d, n=node: d["nodes"][0].update(n), "any" if mentions == "any" else "error",
             "" if mentions == "any" else mentions)
    for name, perspective in [
        ("yfov_zero", {"yfov": 0, "znear": 0.1}), ("yfov_huge", {"yfov": 1e308, "znear": 0.1}),
        ("yfov_negative", {"yfov": -1, "znear": 0.1}), ("znear_negative", {"yfov": 1, "znear": -1}),
        ("aspect_zero", {"yfov": 1, "znear": 0.1, "aspectRatio": 0}),
    ]:
        # Only yfov is read: znear and the aspect ratio may be anything.
        expect = "any" if name in ("znear_negative", "aspect_zero") else "error"
        case(f"camera_{name}", lambda d, p=perspective: d.update(cameras=[{"type": "perspective", "perspective": p}])
             or d["nodes"].append({"camera": 0}) or d["scenes"][0]["nodes"].append(1), expect, "")
    case("camera_orthographic", lambda d: d.update(cameras=[{"type": "orthographic", "orthographic": {
        "xmag": 1e308, "ymag": 0, "znear": 0, "zfar": -1}}]) or d["nodes"].append({"camera": 0})
        or d["scenes"][0]["nodes"].append(1), "any")
    case("camera_collapsed", lambda d: d.update(cameras=[{"type": "perspective", "perspective": {
        "yfov": 1, "znear": 0.1}}]) or d["nodes"].append({"camera": 0, "scale": [0, 0, 0]})
        or d["scenes"][0]["nodes"].append(1), "error", "collapses the view")

    def light(light_def: dict, node: dict | None = None):
        def mutate(d: dict) -> None:
            d["extensionsUsed"] = ["KHR_lights_punctual"]
            d["extensions"] = {"KHR_lights_punctual": {"lights": [light_def]}}
            d["nodes"].append({"extensions": {"KHR_lights_punctual": {"light": 0}}, **(node or {})})
            d["scenes"][0]["nodes"].append(1)
        return mutate
    for name, light_def, node, expect, mentions in [
        ("intensity_huge", {"type": "point", "intensity": 1e308}, None, "error", ""),
        ("intensity_negative", {"type": "point", "intensity": -5}, None, "error", ""),
        ("color_2", {"type": "point", "color": [1, 1]}, None, "error", ""),
        ("color_huge", {"type": "point", "color": [1e300, 1, 1], "intensity": 1e300}, None, "error", ""),
        ("type_unknown", {"type": "laser"}, None, "any", ""),
        ("spot_angles", {"type": "spot", "spot": {"innerConeAngle": 5, "outerConeAngle": -1}}, None, "any", ""),
        ("position_huge", {"type": "point"}, {"translation": [0, 1e300, 0]}, "error", "is not finite"),
    ]:
        case(f"light_{name}", light(light_def, node), expect, mentions)
    case("light_missing", lambda d: d["nodes"].append({"extensions": {"KHR_lights_punctual": {"light": 3}}})
         or d["scenes"][0]["nodes"].append(1), "error", "refers to light 3")
    case("light_not_object", lambda d: d["nodes"].append({"extensions": {"KHR_lights_punctual": 1}})
         or d["scenes"][0]["nodes"].append(1), "any", "")  # tinygltf drops an extension that is not an object
    case("light_index_string", lambda d: d["nodes"].append({"extensions": {"KHR_lights_punctual": {"light": "0"}}})
         or d["scenes"][0]["nodes"].append(1), "error", "is missing or not an integer")

    # Primitives.
    prim = lambda **fields: lambda d: d["meshes"][0]["primitives"][0].update(fields)  # noqa: E731
    case("mode_7", prim(mode=7), "error", "unknown primitive mode 7")
    case("mode_negative", prim(mode=-1), "any")
    case("mode_huge", prim(mode=2**40), "any")
    case("mode_points", prim(mode=0), "loads", "only triangles are rendered")
    case("mode_fan_short", lambda d: prim(mode=6)(d) or d["accessors"][2].update(count=2), "any")
    case("mode_strip", prim(mode=5), "loads")
    case("no_position", lambda d: d["meshes"][0]["primitives"][0]["attributes"].pop("POSITION"), "loads",
         "no POSITION attribute")
    case("no_primitives", lambda d: d["meshes"][0].update(primitives=[]), "any")
    case("index_out_of_range", lambda d: with_buffer(d, TRIANGLE_BIN[:72] + struct.pack("<3I", 0, 1, 3)),
         "error", "index 3 (element 2) is out of range")
    case("index_huge", lambda d: with_buffer(d, TRIANGLE_BIN[:72] + struct.pack("<3I", 0, 2**32 - 1, 2)),
         "error", "is out of range")
    for name, value in (("nan", math.nan), ("inf", math.inf), ("max", 3.4028234663852886e38)):
        payload = struct.pack("<9f", 0, 0, 0, value, 0, 0, 0, 1, 0) + TRIANGLE_BIN[36:]
        expect, mentions = (("loads", "") if name == "max"
                            else ("error", "POSITION (accessors[0]) element 1 is not finite"))
        case(f"position_{name}", lambda d, p=payload: with_buffer(d, p), expect, mentions)
        normals = TRIANGLE_BIN[:36] + struct.pack("<9f", 0, 0, 1, 0, value, 1, 0, 0, 1) + TRIANGLE_BIN[72:]
        case(f"normal_{name}", lambda d, p=normals: with_buffer(d, p), expect,
             "" if name == "max" else "NORMAL (accessors[1]) element 1 is not finite")
    case("position_max_scaled", lambda d: with_buffer(d, struct.pack("<9f", 0, 0, 0, 3e38, 0, 0, 0, 3e38, 0)
                                                       + TRIANGLE_BIN[36:]) and d["nodes"][0].update(scale=[2, 2, 2]),
         "error", "not finite after the node transform")

    # Extensions and extras.
    case("requires_draco", lambda d: d.update(extensionsRequired=["KHR_draco_mesh_compression"]), "error",
         "requires the glTF extension 'KHR_draco_mesh_compression'")
    case("requires_number", lambda d: d.update(extensionsRequired=[3]), "error", "extensionsRequired")
    case("requires_not_array", lambda d: d.update(extensionsRequired="KHR_draco_mesh_compression"), "any")
    for name, extras, mentions in [
        ("unknown_field", {"rt": {"teapots": 3}}, "teapots"),
        ("not_object", {"rt": [1, 2]}, "must be a JSON object"),
        ("sphere_radius", {"rt": {"spheres": [{"radius": -1}]}}, "radius"),
        ("sphere_nan", {"rt": {"spheres": [{"center": ["NaN", 0, 0], "radius": 1}]}}, "center"),
        ("light_infinity", {"rt": {"lights": [{"position": [0, 1, 0], "intensity": "Infinity"}]}}, "intensity"),
        ("motion_unknown_node", {"rt": {"motions": [{"node": "nobody", "translation": [1, 0, 0]}]}}, "nobody"),
        ("motion_no_node", {"rt": {"motions": [{"translation": [1, 0, 0]}]}}, "names no node"),
        ("motion_zero_rotation", {"rt": {"motions": [{"node": "n", "rotation": [0, 0, 0, 0]}]}}, "zero quaternion"),
        ("background_4", {"rt": {"background": [0, 0, 0, 0]}}, "background"),
    ]:
        case(f"extras_{name}", lambda d, e=extras: d["asset"].update(extras=e), "error", mentions)
    case("scene_extras_motion_overflow", lambda d: d["nodes"][0].update(name="n")
         or d["scenes"][0].update(extras={"rt": {"motions": [{"node": "n", "scale": [1e38, 1e38, 1e38],
                                                              "translation": [3e38, 0, 0]}]}}), "error", "")

    # Animations.
    def animation(sampler: dict, channel: dict, keys: bytes, values: bytes, key_count: int, value_count: int,
                  value_type: str = "VEC3"):
        def mutate(d: dict) -> None:
            payload = TRIANGLE_BIN + keys + values
            with_buffer(d, payload)
            d["bufferViews"] += [{"buffer": 0, "byteOffset": 84, "byteLength": len(keys)},
                                 {"buffer": 0, "byteOffset": 84 + len(keys), "byteLength": len(values)}]
            d["accessors"] += [{"bufferView": 3, "componentType": 5126, "count": key_count, "type": "SCALAR"},
                               {"bufferView": 4, "componentType": 5126, "count": value_count, "type": value_type}]
            d["animations"] = [{"samplers": [{"input": 3, "output": 4, **sampler}],
                                "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"},
                                              **channel}]}]
        return mutate
    keys = struct.pack("<2f", 0, 1)
    moves = struct.pack("<6f", 0, 0, 0, 1, 0, 0)
    case("animation_valid", animation({}, {}, keys, moves, 2, 2), "loads")
    case("animation_no_keys", animation({}, {}, keys, moves, 0, 2), "error", "")
    case("animation_count_mismatch", animation({}, {}, keys, moves, 2, 1), "error", "")
    case("animation_interpolation", animation({"interpolation": "BOUNCY"}, {}, keys, moves, 2, 2), "error",
         "unknown interpolation")
    case("animation_cubic_short", animation({"interpolation": "CUBICSPLINE"}, {}, keys, moves, 2, 2), "error", "")
    case("animation_nan", animation({}, {}, keys, struct.pack("<6f", 0, 0, 0, math.nan, 0, 0), 2, 2), "error",
         "is not finite")
    case("animation_keys_nan", animation({}, {}, struct.pack("<2f", math.nan, 1), moves, 2, 2), "any")
    case("animation_keys_backwards", animation({}, {}, struct.pack("<2f", 1, 0), moves, 2, 2), "any")
    case("animation_node_missing", animation({}, {"target": {"node": 5, "path": "translation"}}, keys, moves, 2, 2),
         "error", "refers to node 5")
    case("animation_sampler_missing", animation({}, {"sampler": 3}, keys, moves, 2, 2), "error",
         "refers to sampler 3")
    case("animation_path_weights", animation({}, {"target": {"node": 0, "path": "weights"}}, keys, moves, 2, 2),
         "loads", "not supported")
    case("animation_zero_rotation", animation({}, {"target": {"node": 0, "path": "rotation"}}, keys,
                                              bytes(32), 2, 2, "VEC4"), "error", "zero quaternion")
    case("animation_huge_scale", lambda d: animation({}, {"target": {"node": 0, "path": "scale"}}, keys, struct.pack(
        "<6f", 1, 1, 1, 3e38, 3e38, 3e38), 2, 2)(d) or d["nodes"][0].update(translation=[3e38, 0, 0]), "error",
        "not finite after the node transform")
    case("animation_matrix_node", lambda d: animation({}, {}, keys, moves, 2, 2)(d) or d["nodes"][0].update(
        matrix=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]), "error", "placed by a matrix")
    case("animation_twice", lambda d: animation({}, {}, keys, moves, 2, 2)(d) or d["animations"][0]["channels"].append(
        {"sampler": 0, "target": {"node": 0, "path": "translation"}}), "error", "a second time")


# --- GLB ------------------------------------------------------------------------

def glb_cases(c: Corpus) -> None:
    good = glb(glb_doc(), TRIANGLE_BIN)
    c.add("glb_valid.glb", good, "loads")
    json_length = struct.unpack_from("<I", good, 12)[0]
    bin_header = 20 + json_length

    lengths = set(truncations(len(good), 64)) | {12, 19, 20, bin_header - 1, bin_header, bin_header + 4,
                                                 bin_header + 7, bin_header + 8, bin_header + 9}
    for n in sorted(lengths):
        c.add(f"glb_truncated_{n:04d}.glb", good[:n], "error", "")

    def put(offset: int, value: int, data: bytes = good) -> bytes:
        out = bytearray(data)
        struct.pack_into("<I", out, offset, value)
        return bytes(out)

    for name, data, mentions in [
        ("magic", b"gltf" + good[4:], "is not a GLB file"),
        ("magic_text", dump(glb_doc()), "is not a GLB file"),
        ("version_1", put(4, 1), "GLB version 1 is not supported"),
        ("version_huge", put(4, 0xFFFFFFFF), "is not supported"),
        ("length_0", put(8, 0), "leaves no room for the JSON chunk"),
        ("length_12", put(8, 12), "leaves no room for the JSON chunk"),
        ("length_21", put(8, 21), ""),
        ("length_short", put(8, bin_header + 4), "chunk header after the JSON chunk is truncated"),
        ("length_long", put(8, len(good) + 4), "(truncated file?)"),
        ("length_huge", put(8, 0xFFFFFFFF), "(truncated file?)"),
        ("json_length_0", put(12, 0), ""),
        ("json_length_odd", put(12, json_length - 3), ""),
        ("json_length_long", put(12, json_length + 4), ""),
        ("json_length_huge", put(12, 0xFFFFFFF0), "reaches past the end"),
        ("json_length_wraps", put(12, 0xFFFFFFFF - 19), "reaches past the end"),
        ("json_type", put(16, 0x004E4942), "first chunk is not of type JSON"),
        ("bin_length_0", put(bin_header, 0), ""),
        ("bin_length_6", put(bin_header, 6), "not a positive multiple of 4"),
        ("bin_length_long", put(bin_header, len(TRIANGLE_BIN) + 4), "GLB BIN chunk length"),
        ("bin_length_huge", put(bin_header, 0xFFFFFFFC), "GLB BIN chunk length"),
        ("bin_length_short", put(bin_header, 80), ""),
        ("bin_type", put(bin_header + 4, 0x41424344), "second chunk is not of type BIN"),
        ("json_chunk_garbage", good[:20] + b"\xff" * json_length + good[bin_header:], "invalid JSON"),
        ("json_chunk_nul", good[:20] + b"\0" * json_length + good[bin_header:], "invalid JSON"),
        ("json_chunk_array", b"glTF" + struct.pack("<4I", 2, 24, 4, 0x4E4F534A) + b"[]  ", "not a JSON object"),
    ]:
        c.add(f"glb_{name}.glb", data, "error", mentions)
    c.add("glb_trailing_bytes.glb", good + b"\0" * 16, "loads")
    c.add("glb_extra_chunk.glb", put(8, len(good) + 16, good + struct.pack("<II", 8, 0x12345678) + bytes(8)), "any")

    def variant(name: str, mutate, bin_chunk: bytes | None = TRIANGLE_BIN, expect: str = "error",
                mentions: str = "") -> None:
        d = glb_doc()
        mutate(d)
        c.add(f"glb_{name}.glb", glb(d, bin_chunk), expect, mentions)

    variant("no_bin_chunk", lambda d: None, None, "error", "")
    variant("buffer_longer_than_bin", lambda d: d["buffers"][0].update(byteLength=88), TRIANGLE_BIN, "error",
            "byteLength")
    variant("buffer_length_huge", lambda d: d["buffers"][0].update(byteLength=2**64 - 1))
    variant("second_buffer_no_uri", lambda d: d["buffers"].append({"byteLength": 4}), TRIANGLE_BIN, "error",
            "buffers[1] has no uri")
    variant("buffer_external", lambda d: d["buffers"][0].update(uri="buffer.bin"), TRIANGLE_BIN, "loads")
    variant("buffer_escape", lambda d: d["buffers"][0].update(uri="../outside.bin"), TRIANGLE_BIN, "error",
            "leads outside the scene folder")
    variant("buffer_absolute", lambda d: d["buffers"][0].update(uri="/etc/passwd"), TRIANGLE_BIN, "error",
            "absolute path")
    variant("count_huge", lambda d: d["accessors"][0].update(count=2**32 - 1), TRIANGLE_BIN, "error",
            "reach past the end")
    variant("offset_huge", lambda d: d["accessors"][2].update(byteOffset=2**64 - 4))
    variant("stride_huge", lambda d: d["bufferViews"][0].update(byteStride=2**32 + 12))
    variant("view_past_bin", lambda d: d["bufferViews"][1].update(byteLength=2**32))
    variant("position_nan", lambda d: None, struct.pack("<9f", 0, 0, 0, math.nan, 0, 0, 0, 1, 0) + TRIANGLE_BIN[36:],
            "error", "is not finite")
    variant("position_inf", lambda d: None, struct.pack("<9f", 0, math.inf, 0, 1, 0, 0, 0, 1, 0) + TRIANGLE_BIN[36:],
            "error", "is not finite")
    variant("index_out_of_range", lambda d: None, TRIANGLE_BIN[:72] + struct.pack("<3I", 7, 1, 2), "error",
            "index 7 (element 0) is out of range")
    variant("node_cycle", lambda d: d["nodes"][0].update(children=[0]), TRIANGLE_BIN, "error", "reached twice")
    variant("image_view_past_bin", lambda d: d.update(images=[{"bufferView": 3, "mimeType": "image/png"}])
            or d["bufferViews"].append({"buffer": 0, "byteOffset": 80, "byteLength": 100}), TRIANGLE_BIN, "error",
            "does not lie inside")

    # The image inside the BIN chunk, whole or lying about its size.
    def textured(image: bytes, expect: str, mentions: str) -> tuple:
        d = glb_doc()
        payload = TRIANGLE_BIN + struct.pack("<6f", 0, 0, 1, 0, 0, 1)
        d["buffers"] = [{"byteLength": len(payload) + len(image)}]
        d["bufferViews"] += [{"buffer": 0, "byteOffset": 84, "byteLength": 24},
                             {"buffer": 0, "byteOffset": 108, "byteLength": len(image)}]
        d["accessors"].append({"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC2"})
        d["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 3
        d["meshes"][0]["primitives"][0]["material"] = 0
        d["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
        d["textures"] = [{"source": 0}]
        d["images"] = [{"bufferView": 4, "mimeType": "image/png"}]
        return glb(d, payload + image), expect, mentions
    for name, image, expect, mentions in [
        ("valid", PNG, "loads", ""), ("huge_header", png_header(16000, 16000), "error", "texels"),
        ("truncated", PNG[:50], "loads", "texture ignored"), ("garbage", bytes(range(64)), "loads", "texture ignored"),
    ]:
        data, expect, mentions = textured(image, expect, mentions)
        c.add(f"glb_image_{name}.glb", data, expect, mentions)


# --- OBJ and MTL ---------------------------------------------------------------

def obj_cases(c: Corpus) -> None:
    c.companion("base.mtl", MTL)
    c.add("obj_valid.obj", OBJ, "loads")

    for n in truncations(len(OBJ), 40):
        c.add(f"obj_truncated_{n:04d}.obj", OBJ[:n], "any")
    for n in truncations(len(MTL), 24):
        c.companion(f"obj_truncated_mtl_{n:04d}.mtl", MTL[:n])
        c.add(f"obj_truncated_mtl_{n:04d}.obj", OBJ.replace(b"base.mtl", f"obj_truncated_mtl_{n:04d}.mtl".encode()),
              "any")

    def case(name: str, data: bytes, expect: str = "error", mentions: str = "") -> None:
        c.add(f"obj_{name}.obj", data, expect, mentions)

    # Indices: huge, negative, zero, of the wrong kind.
    for name, face, mentions in [
        ("index_past_end", "f 1 2 4", "vertex index is out of range (3 vertices)"),
        ("index_int_max", "f 1 2 2147483647", "vertex index is out of range"),
        ("index_int_overflow", "f 1 2 2147483648", ""),
        ("index_huge", "f 1 2 99999999999999999999999", ""),
        ("index_negative_past_start", "f 1 2 -4", "vertex index is out of range"),
        ("index_int_min", "f 1 2 -2147483648", ""),
        ("index_negative_huge", "f -99999999999999999999 1 2", ""),
        ("index_zero", "f 1 2 0", "zero value for face index. line 4.)"),
        ("normal_past_end", "f 1//1 2//1 3//2", "normal index is out of range"),
        ("normal_int_min", "f 1//-2147483648 2//1 3//1", ""),
        ("texcoord_past_end", "f 1/2 2/1 3/1", "texture coordinate index is out of range"),
        ("texcoord_huge", "f 1/2147483647 2/1 3/1", "texture coordinate index is out of range"),
        ("index_not_number", "f 1 2 x", ""),
        ("index_empty_parts", "f 1/ 2// 3///", ""),
        ("face_two_corners", "f 1 2", ""),
        ("face_one_corner", "f 1", ""),  # tinyobjloader's warning "Degenerated face found\n." (no "." warning)
        ("face_no_corner", "f", ""),
    ]:
        lines = TRI + (("vn 0 0 1",) if "normal" in name else ()) + (("vt 0 0",) if "texcoord" in name else ())
        expect = "error" if mentions else "any"
        if name in ("face_two_corners", "face_one_corner"):
            expect, mentions = "loads", "Degenerated face found"
        case(name, obj(*lines, face, mtllib=None), expect, mentions)
    for corners in (256, 258, 300, 1000):
        verts = [f"v {math.cos(i * 0.01):.6f} {math.sin(i * 0.01):.6f} 0" for i in range(corners)]
        face = "f " + " ".join(str(i + 1) for i in range(corners))
        case(f"face_{corners}_corners", obj(*verts, face, mtllib=None), "error", "a face with more than 255 vertices")
    case("face_255_corners", obj(*[f"v {math.cos(i * 0.02):.6f} {math.sin(i * 0.02):.6f} 0" for i in range(255)],
                                 "f " + " ".join(str(i + 1) for i in range(255)), mtllib=None), "loads")
    case("many_corners_one_line", obj(*TRI, "f " + " ".join(["1 2 3"] * 20000), mtllib=None), "error",
         "more than 255 vertices")
    case("line_out_of_range", obj(*TRI, "l 1 99", "f 1 2 3", mtllib=None), "any")
    case("point_out_of_range", obj(*TRI, "p -99 4", "f 1 2 3", mtllib=None), "any")
    case("lines_only", obj(*TRI, "l 1 2 3", mtllib=None), "loads", "only faces are rendered")

    # Numbers tinyobjloader would read as 0, or beyond float.
    for name, line, mentions in [
        ("v_nan", "v nan 0 0", "v value 'nan' is not a finite number"),
        ("v_inf", "v 0 inf 0", "v value 'inf' is not a finite number"),
        ("v_1e39", "v 1e39 0 0", "v #4 is not a finite float"),
        ("v_1e999", "v 0 0 1e999", "v value '1e999' is not a finite number"),
        ("v_0e999", "v 0e999 0 0", "v #4 is not a finite float"),  # 0 * 10^999 to from_chars, NaN to tinyobj
        ("v_exponent_overflow", "v 1e99999999999999 0 0", "is not a finite number"),
        ("v_letters", "v 1 x 0", "v value 'x' is not a finite number"),
        ("v_hex", "v 0x10 0 0", "is not a finite number"),
        ("v_one_component", "v 1", ""),
        ("v_colours", "v 0 0 0 1 0.5 0", ""),
        ("v_colours_nan", "v 0 0 0 nan 0 0", "is not a finite number"),
        ("vn_nan", "vn nan 0 1", "vn value 'nan'"),
        ("vn_1e39", "vn 1e39 0 1", "vn #1 is not a finite float"),
        ("vt_nan", "vt 0.5 NaN", "vt value 'NaN'"),
        ("vt_1e39", "vt 1e39 0", "vt #1 is not a finite float"),
        ("vw_huge", "vw 1 2147483648 1e300 -99999999999", ""),
        ("vp_nan", "vp nan nan", ""),
    ]:
        expect = "error" if mentions else "any"
        case(name, obj(*TRI, line, "f 1 2 3", mtllib=None), expect, mentions)

    # Material libraries and textures outside the folder, missing, or broken.
    for name, mtllib, expect, mentions in [
        ("mtllib_parent", "../outside.mtl", "error", "mtllib '../outside.mtl' leads outside"),
        ("mtllib_symlink", "escape/outside.mtl", "error", "leads outside the scene folder"),
        ("mtllib_absolute", "/etc/passwd", "error", "absolute path"),
        ("mtllib_url", "http://example.com/a.mtl", "error", "is a URL"),
        ("mtllib_missing", "missing.mtl", "loads", "material library 'missing.mtl' not found"),
        ("mtllib_folder", "folder.bin", "error", "is not a regular file"),
        ("mtllib_binary", "buffer.bin", "any", ""),
        ("mtllib_many", " ".join(["missing.mtl"] * 50) + " base.mtl", "any", ""),
        ("mtllib_empty", "", "any", ""),
    ]:
        case(name, obj(*TRI, "usemtl plain", "f 1 2 3", mtllib=mtllib), expect, mentions)
    case("usemtl_unknown", obj(*TRI, "usemtl nothing", "f 1 2 3"), "any")
    # Names that are not UTF-8, or whose quote would cut a character in two, in messages.
    case("mtllib_bad_utf8", obj(*TRI, "f 1 2 3", mtllib=None) + b"mtllib \xff\xfe\x1b[31m.mtl\n", "loads",
         "material library '??\u003f[31m.mtl' not found")
    case("mtllib_long_utf8", obj(*TRI, "f 1 2 3", mtllib="\u00e9" * 100 + ".mtl"), "loads",
         "'" + "\u00e9" * 60 + "...'")
    case("usemtl_bad_utf8", obj(*TRI, "usemtl @@", "f 1 2 3").replace(b"@@", b"\xff\xfe"), "loads",
         "material [ '??' ] not found")
    case("object_bad_utf8", obj(*TRI, "o \u00e9", "f 1 2 3", mtllib=None).replace(b"\xc3\xa9", b"\xc3"), "loads")
    case("usemtl_before_mtllib", b"usemtl plain\n" + obj(*TRI, "f 1 2 3"), "any")

    def mtl_case(name: str, mtl: str, expect: str = "error", mentions: str = "", uses: str = "m") -> None:
        c.companion(f"obj_mtl_{name}.mtl", mtl.encode())
        c.add(f"obj_mtl_{name}.obj", obj(*TRI, f"usemtl {uses}", "f 1 2 3", mtllib=f"obj_mtl_{name}.mtl"),
              expect, mentions)
    for name, body, expect, mentions in [
        ("kd_negative", "Kd 0.5 -1 0.5", "error", "has a negative Kd, Ks or Ns"),
        ("kd_nan", "Kd nan 0 0", "any", ""),
        ("kd_1e400", "Kd 1e400 0 0", "error", "not a finite float"),
        ("kd_exponent_overflow", "Kd 1e99999999999999 0 0", "any", ""),
        ("ns_1e400", "Ns 1e400", "error", "has a Kd, Ks or Ns"),
        ("ns_negative", "Ns -5", "error", "negative"),
        ("ni_zero_transparent", "d 0.5\nNi 0", "error", "with Ni 0, expected an index of refraction of at least 1"),
        ("ni_1e400", "d 0.5\nNi 1e400", "error", "d, Tr or Ni"),
        ("d_nan", "d nan", "any", ""),
        ("tr_huge", "Tr 1e400", "error", "d, Tr or Ni"),
        ("illum_huge", "illum 99999999999999", "any", ""),
        ("map_parent", "map_Kd ../outside.bin", "error", "map_Kd '../outside.bin' leads outside"),
        ("map_absolute", "map_Kd /etc/passwd", "error", "absolute path"),
        ("map_symlink", "map_Kd escape/outside.bin", "error", "leads outside the scene folder"),
        ("map_url", "map_Kd https://example.com/t.png", "error", "is a URL"),
        ("map_missing", "map_Kd missing.png", "loads", "not found: texture ignored"),
        ("map_not_image", "map_Kd buffer.bin", "loads", "is not a PNG, JPEG, BMP, TGA or WebP image"),
        ("map_folder", "map_Kd folder.bin", "error", "is not a regular file"),
        ("map_options_huge", "map_Kd -s 1e999 1e999 1e999 -o -1e999 0 0 -texres 99999999999 -bm nan image.png",
         "any", ""),
        ("map_options_only", "map_Kd -clamp on -blendu off", "any", ""),
        ("map_option_unfinished", "map_Kd -s", "any", ""),
        ("newmtl_empty", "newmtl\nKd 1 1 1", "any", ""),
        ("binary", "\x00\x01\x02\xff" * 64, "any", ""),
    ]:
        mtl_case(name, f"newmtl m\n{body}\n", expect, mentions)

    # Text that is not text, and lines that never end.
    case("binary", bytes(range(256)) * 8, "any")
    case("nul_bytes", obj(*TRI, "f 1 2 3", mtllib=None).replace(b"\n", b"\0\n"), "any")
    case("cr_only", obj(*TRI, "f 1 2 3", mtllib=None).replace(b"\n", b"\r"), "any")
    case("crlf", obj(*TRI, "f 1 2 3", mtllib=None).replace(b"\n", b"\r\n"), "loads")
    case("long_line", obj(*TRI, "f 1 2 3", "o " + "x" * 200000, mtllib=None), "any")
    case("long_number", obj("v " + "9" * 5000 + " 0 0", *TRI[1:], "f 1 2 3", mtllib=None), "error", "")
    case("many_tokens", obj("v " + " ".join(["0"] * 50000), *TRI, "f 2 3 4", mtllib=None), "any")
    case("empty", b"", "loads")
    case("only_comments", b"# nothing\n#\n", "loads")
    case("degenerate", obj("v 0 0 0", "v 0 0 0", "v 0 0 0", "f 1 2 3", mtllib=None), "loads", "degenerate")


# --- Sidecars (<scene>.rt.json) ---------------------------------------------------

SIDECAR_OBJ = obj("o a", *TRI, "f 1 2 3", "o b", "v 0 0 1", "v 1 0 1", "v 0 1 1", "f 4 5 6", mtllib=None)
VALID_SIDECAR = {
    "lights": [{"position": [0, 1, 0], "color": [1, 1, 1], "intensity": 2, "radius": 0.1}],
    "spheres": [{"center": [0, 0, -1], "radius": 0.5, "material": {"diffuse": [0.5, 0.5, 0.5]}}],
    "background": [0.1, 0.1, 0.1],
    "cameras": [{"name": "front", "camera": {"position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0],
                                             "fov_y": 40}}],
    "motions": [{"node": "a", "translation": [0.1, 0, 0]}, {"node": "b", "rotation": [0, 0, 0.38268343, 0.9238795]}],
}


def sidecar_cases(c: Corpus) -> None:
    def case(name: str, sidecar: bytes, expect: str = "error", mentions: str = "", scene: bytes = SIDECAR_OBJ,
             ext: str = "obj") -> None:
        c.companion(f"sidecar_{name}.rt.json", sidecar)
        c.add(f"sidecar_{name}.{ext}", scene, expect, mentions)

    valid = json.dumps(VALID_SIDECAR, indent=1).encode()
    case("valid", valid, "loads")
    for n in truncations(len(valid), 24):
        case(f"truncated_{n:04d}", valid[:n], "error", "")

    def changed(**fields) -> bytes:
        return json.dumps({**VALID_SIDECAR, **fields}).encode()
    for name, data, mentions in [
        ("empty", b"", ""), ("array", b"[]", ""), ("null", b"null", ""), ("binary", bytes(range(256)), ""),
        ("unknown_field", changed(teapots=1), "teapots"),
        ("deep", b'{"spheres": [' * 5000 + b"]}" * 5000, ""),
        ("deep_unknown", b'{"x": ' * 100000 + b"1" + b"}" * 100000, ""),
        ("nan_literal", b'{"background": [NaN, 0, 0]}', ""),
        ("sphere_radius_negative", changed(spheres=[{"radius": -1}]), "radius"),
        ("sphere_radius_nan", changed(spheres=[{"radius": "NaN"}]), "radius"),
        ("sphere_center_infinity", changed(spheres=[{"center": ["Infinity", 0, 0], "radius": 1}]), "center"),
        ("sphere_center_2", changed(spheres=[{"center": [0, 0], "radius": 1}]), "center"),
        ("sphere_center_1e39", changed(spheres=[{"center": [1e39, 0, 0], "radius": 1}]), ""),
        ("sphere_material_nan", changed(spheres=[{"center": [0, 0, 0], "radius": 1, "material": {"shininess": "NaN"}}]),
         "shininess"),
        ("light_intensity_huge", changed(lights=[{"color": [3e38, 3e38, 3e38], "intensity": 3e38}]), "intensity"),
        ("light_intensity_nan", changed(lights=[{"intensity": "NaN"}]), "intensity"),
        ("light_position_1e39", changed(lights=[{"position": [1e39, 0, 0]}]), ""),
        ("light_radius_negative", changed(lights=[{"radius": -1}]), "radius"),
        ("background_4", changed(background=[0, 0, 0, 0]), "background"),
        ("background_string", changed(background="black"), "background"),
        ("camera_no_camera", changed(cameras=[{"name": "x"}]), ""),
        ("camera_fov_0", changed(cameras=[{"camera": {"position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0],
                                                      "fov_y": 0}}]), "fov_y"),
        # Cameras are checked when a render uses them (camera.cpp), not when loaded.
        ("camera_collapsed", changed(cameras=[{"camera": {"position": [0, 0, 0], "target": [0, 0, 0],
                                                          "up": [0, 1, 0]}}]), "any"),
        ("camera_up_zero", changed(cameras=[{"camera": {"position": [0, 0, 3], "target": [0, 0, 0],
                                                        "up": [0, 0, 0]}}]), "any"),
        ("motion_no_node", changed(motions=[{"translation": [1, 0, 0]}]), "names no node"),
        ("motion_unknown_node", changed(motions=[{"node": "zebra"}]), "has no object or group 'zebra'"),
        ("motion_twice", changed(motions=[{"node": "a"}, {"node": "a"}]), "has a motion already"),
        ("motion_zero_rotation", changed(motions=[{"node": "a", "rotation": [0, 0, 0, 0]}]), "zero quaternion"),
        ("motion_rotation_3", changed(motions=[{"node": "a", "rotation": [0, 0, 1]}]), "rotation"),
        ("motion_huge_scale", changed(motions=[{"node": "a", "scale": [3e38, 3e38, 3e38],
                                                "translation": [3e38, 0, 0]}]), "out of range"),
        ("motion_scale_1e39", changed(motions=[{"node": "a", "scale": [1e39, 1, 1]}]), ""),
        ("motion_node_long", changed(motions=[{"node": "x" * 100000}]), "has no object or group"),
        ("motion_node_control", changed(motions=[{"node": "\u0001\n\u001b[31m"}]), "has no object or group"),
        ("string_for_number", changed(background=["0", "0", "0"]), "any"),
        ("radius_infinity_bare", changed(spheres=[{"radius": math.inf}]), ""),
        ("duplicate_keys", b'{"background": [0, 0, 0], "background": [1, 1, 1]}', "any"),
    ]:
        case(name, data, "any" if mentions == "any" else "error", "" if mentions == "any" else mentions)
    many = json.dumps({"spheres": [{"center": [i, 0, 0], "radius": 0.1} for i in range(5000)]}).encode()
    case("many_spheres", many, "loads")

    # Beside a glTF, whose nodes the motions move.
    doc = triangle_doc("buffer.bin")
    doc["nodes"] = [{"name": "a", "mesh": 0}, {"name": "b", "mesh": 0, "scale": [1e30, 1e30, 1e30]}]
    doc["scenes"][0]["nodes"] = [0, 1]
    case("gltf_valid", json.dumps({"motions": [{"node": "a", "translation": [1, 0, 0]}]}).encode(), "loads",
         scene=dump(doc), ext="gltf")
    case("gltf_unknown_node", json.dumps({"motions": [{"node": "zebra"}]}).encode(), "error", "zebra",
         scene=dump(doc), ext="gltf")
    case("gltf_motion_overflow", json.dumps({"motions": [{"node": "b", "scale": [3e38, 3e38, 3e38],
                                                          "translation": [3e38, 0, 0]}]}).encode(),
         "error", "not finite", scene=dump(doc), ext="gltf")
    case("glb_bad", b'{"lights": [{"position": [0, 1, 0], "intensity": -1}]}', "error", "intensity",
         scene=glb(glb_doc(), TRIANGLE_BIN),
         ext="glb")


# --- Writing -------------------------------------------------------------------

def build() -> Corpus:
    c = Corpus()
    c.companion("buffer.bin", TRIANGLE_BIN)
    c.companion("sub/buffer.bin", TRIANGLE_BIN)
    c.companion("image.png", PNG)
    gltf_cases(c)
    glb_cases(c)
    obj_cases(c)
    sidecar_cases(c)
    return c


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
