"""Hostile glTF files about where the data is: accessors, sparse accessors,
buffer views, buffers, data: URIs, and URIs that lead out of the scene folder.

These are the cases that could make the loader read past an allocation or
outside the folder it was given, so they get the widest ranges of lying counts,
offsets and lengths (2^31, 2^32, 2^64 - 1, ...).
"""

from __future__ import annotations

import base64
import struct

from .bases import TRIANGLE_BIN, Corpus, accessor, gltf_case, textured_doc, triangle_doc, view, with_buffer


def buffer_cases(c: Corpus) -> None:
    case = gltf_case(c)

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
        # Without a view an accessor reads as zeros: degenerate positions, or indices 0, 0, 0.
        case(f"{label}_no_view", lambda d, i=i: d["accessors"][i].pop("bufferView"), "loads", "degenerate")
        case(f"{label}_no_view_huge", lambda d, i=i: [d["accessors"][i].pop("bufferView"),
                                                       d["accessors"][i].update(count=2**40)],
             "error", "without a bufferView: held in memory")
        case(f"{label}_view_missing", accessor(i, bufferView=99), "error", "")
    case("accessor_missing", lambda d: d["meshes"][0]["primitives"][0]["attributes"].update(NORMAL=40), "error",
         "refers to accessor 40")
    case("accessor_negative", lambda d: d["meshes"][0]["primitives"][0].update(indices=-7), "error", "")
    # KHR_mesh_quantization's integer types read the float data as integers: odd, but valid.
    case("positions_short", accessor(0, componentType=5122), "any")
    case("positions_int", accessor(0, componentType=5124), "error", "unsupported component type INT")
    case("normals_bytes_unnormalized", accessor(1, componentType=5120), "error", "components that are not normalized")
    case("normals_bytes", accessor(1, componentType=5120, normalized=True), "any")
    case("positions_bad_component", accessor(0, componentType=1), "error", "")
    case("positions_vec4", accessor(0, type="VEC4"), "error", "has type VEC4")
    case("positions_bad_type", accessor(0, type="VEC9"), "error", "")
    case("indices_float", accessor(2, componentType=5126), "error", "unsupported component type FLOAT")
    case("indices_count_not_triangles", accessor(2, count=2), "error", "not a multiple of 3")
    def quantized(d: dict) -> None:
        """KHR_mesh_quantization: SHORT positions under a dequantizing scale, BYTE normals, USHORT uv."""
        with_buffer(d, struct.pack("<12h", 0, 0, 0, 0, 1000, 0, 0, 0, 0, 1000, 0, 0)
                    + struct.pack("<12b", 0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0)
                    + struct.pack("<6H", 0, 0, 65535, 0, 0, 65535) + struct.pack("<3I", 0, 1, 2))
        d["bufferViews"] = [{"buffer": 0, "byteOffset": 0, "byteLength": 24, "byteStride": 8},
                            {"buffer": 0, "byteOffset": 24, "byteLength": 12, "byteStride": 4},
                            {"buffer": 0, "byteOffset": 36, "byteLength": 12},
                            {"buffer": 0, "byteOffset": 48, "byteLength": 12}]
        d["accessors"] = [{"bufferView": 0, "componentType": 5122, "count": 3, "type": "VEC3"},
                          {"bufferView": 1, "componentType": 5120, "normalized": True, "count": 3, "type": "VEC3"},
                          {"bufferView": 2, "componentType": 5123, "normalized": True, "count": 3, "type": "VEC2"},
                          {"bufferView": 3, "componentType": 5125, "count": 3, "type": "SCALAR"}]
        d["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2
        d["meshes"][0]["primitives"][0]["indices"] = 3
        d["nodes"][0]["scale"] = [0.001] * 3
        d["extensionsUsed"] = d["extensionsRequired"] = ["KHR_mesh_quantization"]

    def extra_attributes(d: dict) -> None:
        """TEXCOORD_1, COLOR_0 (the normals as colours) and TANGENT (VEC4 over the first 48 bytes)."""
        d["bufferViews"].append({"buffer": 0, "byteOffset": 0, "byteLength": 48})
        d["accessors"].append({"bufferView": len(d["bufferViews"]) - 1, "componentType": 5126, "count": 3,
                               "type": "VEC4"})
        d["meshes"][0]["primitives"][0]["attributes"].update(TEXCOORD_1=3, COLOR_0=1, TANGENT=len(d["accessors"]) - 1)
        d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1

    # Sparse: indices from the index view (0, 1, 2), values from the positions' view, which as UNSIGNED_INT
    # are 0, 0, 0, 0x3f800000, ... and the normals' 0, 0, 0x3f800000, ...
    def sparse(count=1, indices=None, values=None):
        return accessor(0, sparse={"count": count,
                                   "indices": {"bufferView": 2, "componentType": 5125, **(indices or {})},
                                   "values": {"bufferView": 0, **(values or {})}})
    case("sparse", sparse(), "loads")
    case("sparse_all", sparse(3), "loads")
    case("sparse_no_view", lambda d: [sparse(3)(d), d["accessors"][0].pop("bufferView")], "loads")
    case("sparse_indices", lambda d: d["accessors"][2].update(sparse={
        "count": 2, "indices": {"bufferView": 2, "byteOffset": 4, "componentType": 5125},
        "values": {"bufferView": 2, "byteOffset": 4}}), "loads")
    case("sparse_indices_no_view", lambda d: [d["accessors"][2].pop("bufferView"), d["accessors"][2].update(sparse={
        "count": 2, "indices": {"bufferView": 2, "byteOffset": 4, "componentType": 5125},
        "values": {"bufferView": 2, "byteOffset": 4}})], "loads")
    case("indices_marked_no_view", lambda d: d["accessors"][2].update(extensions={"RT_no_buffer_view": {}}), "loads",
         "degenerate")
    case("sparse_count_too_large", sparse(4), "error", "sparse.count 4, which is not between 1 and its count 3")
    case("sparse_count_zero", sparse(0), "error", "sparse.count 0")
    case("sparse_count_negative", sparse(-1), "error", "")
    case("sparse_index_out_of_range", sparse(1, {"bufferView": 0, "byteOffset": 12}), "error", "out of range")
    case("sparse_not_increasing", sparse(2, {"bufferView": 1}), "error", "must be strictly increasing")
    case("sparse_indices_past_view", sparse(1, {"byteOffset": 12}), "error",
         "sparse.indices has 1 elements from byteOffset 12, which reach past the end")
    case("sparse_values_past_view", sparse(1, values={"byteOffset": 30}), "error",
         "sparse.values has 1 elements from byteOffset 30, which reach past the end")
    case("sparse_values_view_missing", sparse(1, values={"bufferView": 99}), "error",
         "sparse.values refers to bufferView 99")
    case("sparse_index_float", sparse(1, {"componentType": 5126}), "error",
         "sparse.indices of unsupported component type FLOAT")
    case("sparse_offset_negative", sparse(1, {"byteOffset": -4}), "error", "")
    case("quantized", quantized, "loads")
    case("attributes", extra_attributes, "loads", doc=textured_doc({"uri": "image.png"}))
    case("sparse_huge_no_view", lambda d: [sparse(3)(d), d["accessors"][0].pop("bufferView"),
                                           d["accessors"][0].update(count=2**40)],
         "error", "held in memory they would take more than")
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
        ("junk", "data:application/octet-stream;base64," + b64[:40] + "!!!!" + b64[44:], "malformed data: URI"),
        ("padding", "data:application/octet-stream;base64,====" + b64, "padding before its end"),
        ("empty_payload", "data:application/octet-stream;base64,", "declares byteLength"),
        ("not_base64", "data:application/octet-stream," + "A" * 112, "is a malformed data: URI: it is not base64"),
        ("no_media_type", "data:;base64," + b64, "data: URI"),
        ("text_media_type", "data:text/plain;base64," + b64, "a buffer's must be application/octet-stream"),
        ("image_media_type", "data:image/png;base64," + b64, "a buffer's must be application/octet-stream"),
        ("stray_digit", "data:application/octet-stream;base64," + b64 + "A", "stray last character"),
        ("no_comma", "data:application/octet-stream;base64", "data: URI"),
        ("bare", "data:", "data: URI"),
        ("gltf_buffer", "data:application/gltf-buffer;base64," + b64 + "====", "any"),
    ]:
        case(f"data_uri_{name}", lambda d, u=uri: d["buffers"][0].update(uri=u),
             "any" if mentions == "any" else "error", "" if mentions == "any" else mentions)
    case("data_uri_gltf_buffer_valid", lambda d: d["buffers"][0].update(uri="data:application/gltf-buffer;base64,"
                                                                         + b64), "loads")

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
