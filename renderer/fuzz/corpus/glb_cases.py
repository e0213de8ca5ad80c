"""Hostile GLB files: the binary container around a glTF document.

The JSON inside is already covered by the glTF cases, so these mostly break
the container: truncations at every header boundary, chunk lengths and types
that lie, and a BIN chunk that does not hold what the document says it does
(buffers, views, an embedded image).
"""

from __future__ import annotations

import math
import struct

from .bases import PNG, TRIANGLE_BIN, Corpus, dump, glb, glb_doc, png_header, truncations


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
