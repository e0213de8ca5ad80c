"""Hostile compressed geometry: EXT_meshopt_compression and
KHR_draco_mesh_compression.

Decoders are where a lying count turns into a huge allocation or a read past
the stream, so the cases start from valid streams and break them or lie about
them: truncated and garbage streams, counts, strides, modes, filters,
attribute ids. The streams are fixed bytes, as this script may use no library
but the standard one.
"""

from __future__ import annotations

import copy

from .bases import Corpus, data_uri, dump, glb, triangle_doc

# The triangle's positions, normals and indices as meshoptimizer 0.18 encodes them
# (meshopt_encodeVertexBuffer with a stride of 12, meshopt_encodeIndexBuffer),
# and as Draco 1.5.5 does (draco::Encoder, positions quantized to 14 bits and
# normals to 10; attribute ids 0 and 1), and three of its points as a Draco
# point cloud: bytes from the libraries, as this script may use none.
MESHOPT_POSITIONS = bytes.fromhex(
    "a00000013c000000ffff013c0000007e7d0000010c000000ff010c0000007e00000000000000000000000000000000000000"
    "0000000000000000000000000000000000")
MESHOPT_NORMALS = bytes.fromhex(
    "a0000000000000000000000000000000000000000000000000000000000000000000000000000000000000803f")
MESHOPT_TRIANGLES = bytes.fromhex("e0f0007687566778a9866589689801690000")
DRACO_TRIANGLE = bytes.fromhex(
    "445241434f020201010000000301010100000107ff011101010002ff000000000001000903000002010109030001030101010003"
    "035515ad2a03047081311000000000ff3f00000000000000000000000000000000803f0e000301000a03ad2a1b551503af5a81"
    "00fe03ff030000ff0100000a")
DRACO_POINTS = bytes.fromhex(
    "445241434f0203000000000300000001010009030000000000000000000000000000000000803f000000000000000000000000"
    "0000803f00000000")


def meshopt_doc() -> tuple[dict, bytes]:
    """The triangle, its views decoded from streams in buffers[0] into a fallback
    buffer without data (buffers[1]); and those streams."""
    doc = triangle_doc()
    streams, extensions = b"", []
    for stream, stride, mode in [(MESHOPT_POSITIONS, 12, "ATTRIBUTES"), (MESHOPT_NORMALS, 12, "ATTRIBUTES"),
                                 (MESHOPT_TRIANGLES, 4, "TRIANGLES")]:
        streams += b"\0" * (-len(streams) % 4)
        extensions.append({"buffer": 0, "byteOffset": len(streams), "byteLength": len(stream),
                           "byteStride": stride, "count": 3, "mode": mode})
        streams += stream
    for view, extension in zip(doc["bufferViews"], extensions):
        view.update(buffer=1, extensions={"EXT_meshopt_compression": extension})
        if extension["mode"] == "ATTRIBUTES":
            view["byteStride"] = 12
    doc["buffers"] = [{"byteLength": len(streams), "uri": data_uri(streams)},
                      {"byteLength": 84, "extensions": {"EXT_meshopt_compression": {"fallback": True}}}]
    doc["extensionsUsed"] = doc["extensionsRequired"] = ["EXT_meshopt_compression"]
    return doc, streams


def draco_doc(stream: bytes = DRACO_TRIANGLE) -> dict:
    """The triangle as a Draco primitive: accessors without views, the stream in bufferViews[0]."""
    doc = triangle_doc()
    doc["buffers"] = [{"byteLength": len(stream), "uri": data_uri(stream)}]
    doc["bufferViews"] = [{"buffer": 0, "byteLength": len(stream)}]
    for accessor in doc["accessors"]:
        del accessor["bufferView"]
    doc["accessors"][2]["componentType"] = 5123
    doc["meshes"][0]["primitives"][0]["extensions"] = {
        "KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0, "NORMAL": 1}}}
    doc["extensionsUsed"] = doc["extensionsRequired"] = ["KHR_draco_mesh_compression"]
    return doc


def compressed_cases(c: Corpus) -> None:
    def as_glb(doc: dict, payload: bytes) -> bytes:
        """`doc` as a GLB with `payload` (its buffers[0]) in the BIN chunk."""
        d = copy.deepcopy(doc)
        d["buffers"][0] = {"byteLength": len(payload)}
        return glb(d, payload)

    good, streams = meshopt_doc()
    c.add("gltf_meshopt_valid.gltf", dump(good), "loads")
    c.add("glb_meshopt_valid.glb", as_glb(good, streams), "loads")

    def meshopt(name: str, mutate, mentions: str, expect: str = "error") -> None:
        d = copy.deepcopy(good)
        mutate(d, [v["extensions"]["EXT_meshopt_compression"] for v in d["bufferViews"]])
        c.add(f"gltf_meshopt_{name}.gltf", dump(d), expect, mentions)
        c.add(f"glb_meshopt_{name}.glb", as_glb(d, streams), expect, mentions)

    meshopt("truncated", lambda d, e: e[0].update(byteLength=40), "cannot be decoded")
    meshopt("header_version", lambda d, e: e[1].update(byteOffset=e[1]["byteOffset"] + 1), "cannot be decoded")
    meshopt("count_lies", lambda d, e: e[0].update(count=4), "decodes to 48 bytes, but the bufferView's byteLength")
    meshopt("count_lies_with_view", lambda d, e: e[0].update(count=300000) or d["bufferViews"][0].update(
        byteLength=3600000), "more than its 67 bytes can encode")
    meshopt("count_huge", lambda d, e: e[0].update(count=2**27), "vertices a scene may have")
    # tinygltf 2.7 would truncate these to int (2^32 to 0): refused before it parses.
    meshopt("count_past_int", lambda d, e: e[0].update(count=2**40), "count 1099511627776 is out of range")
    meshopt("offset_past_int", lambda d, e: e[2].update(byteOffset=2**32), "byteOffset 4294967296 is out of range")
    meshopt("count_zero", lambda d, e: e[2].update(count=0), "has count 0")
    meshopt("indices_lie", lambda d, e: e[2].update(count=300) or d["bufferViews"][2].update(byteLength=1200),
            "claims 300 indices")
    meshopt("past_buffer", lambda d, e: e[2].update(byteOffset=120), "reaches past the end of buffers[0]")
    meshopt("buffer_missing", lambda d, e: e[0].update(buffer=5), "refers to buffer 5, which does not exist")
    meshopt("from_fallback", lambda d, e: e[0].update(buffer=1), "reaches past the end of buffers[1]")
    meshopt("mode_invalid", lambda d, e: e[0].update(mode="STRIPS"), "has mode 'STRIPS'")
    meshopt("mode_missing", lambda d, e: e[0].pop("mode"), "has mode ''")
    meshopt("filter_invalid", lambda d, e: e[0].update(filter="ZIGZAG"), "has filter 'ZIGZAG'")
    meshopt("filter_quaternion", lambda d, e: e[0].update(filter="QUATERNION"), "has filter QUATERNION")
    meshopt("filter_exponential", lambda d, e: e[0].update(filter="EXPONENTIAL"), "", "any")
    meshopt("filter_on_indices", lambda d, e: e[2].update(filter="OCTAHEDRAL"), "has a filter but mode is not")
    meshopt("stride_odd", lambda d, e: e[0].update(byteStride=6), "ATTRIBUTES need a multiple of 4")
    meshopt("stride_indices", lambda d, e: e[2].update(byteStride=1), "TRIANGLES need 2 or 4")
    meshopt("stride_mismatch", lambda d, e: e[0].update(byteStride=16), "")
    meshopt("as_sequence", lambda d, e: e[2].update(mode="INDICES"), "cannot be decoded")
    meshopt("not_object", lambda d, e: d["bufferViews"][0]["extensions"].update(EXT_meshopt_compression=7),
            "is not a JSON object")
    meshopt("plain_view_of_fallback", lambda d, e: d["bufferViews"][0].pop("extensions"),
            "reaches past the end of buffers[1]")
    meshopt("fallback_false", lambda d, e: d["buffers"][1]["extensions"]["EXT_meshopt_compression"].update(
        fallback=False), "buffers[1] has no uri")
    meshopt("not_required", lambda d, e: d.pop("extensionsRequired"), "", "loads")

    c.add("gltf_draco_valid.gltf", dump(draco_doc()), "loads")
    c.add("glb_draco_valid.glb", as_glb(draco_doc(), DRACO_TRIANGLE), "loads")

    def draco(name: str, mutate, mentions: str, stream: bytes = DRACO_TRIANGLE, expect: str = "error") -> None:
        d = draco_doc(stream)
        mutate(d, d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"])
        c.add(f"gltf_draco_{name}.gltf", dump(d), expect, mentions)
        c.add(f"glb_draco_{name}.glb", as_glb(d, stream), expect, mentions)

    nothing = lambda d, e: None  # noqa: E731
    for n in (1, 4, 5, 20, 50, len(DRACO_TRIANGLE) - 1):
        draco(f"truncated_{n:03d}", lambda d, e, n=n: d["bufferViews"][0].update(byteLength=n), "Draco")
    draco("garbage", nothing, "Draco", bytes(range(7, 7 + 115)))
    draco("magic_only", nothing, "Draco", DRACO_TRIANGLE[:5] + b"\xff" * 110)
    draco("point_cloud", nothing, "holds a Draco point cloud", DRACO_POINTS)
    draco("attribute_id_missing", lambda d, e: e["attributes"].update(POSITION=9), "names Draco attribute 9")
    draco("attribute_id_negative", lambda d, e: e["attributes"].update(NORMAL=-1), "names Draco attribute -1")
    draco("attribute_id_text", lambda d, e: e["attributes"].update(NORMAL="1"), "not an integer")
    draco("attribute_unknown", lambda d, e: e["attributes"].update(TEXCOORD_0=1), "not one of the primitive's")
    draco("attributes_missing", lambda d, e: e.pop("attributes"), "has no attributes object")
    draco("count_lies", lambda d, e: d["accessors"][0].update(count=4), "but Draco decoded 3 points")
    draco("count_huge", lambda d, e: d["accessors"][0].update(count=2**40), "more than a scene may have")
    draco("indices_lie", lambda d, e: d["accessors"][2].update(count=6), "but Draco decoded 1 triangles")
    draco("indices_huge", lambda d, e: d["accessors"][2].update(count=2**33), "more than a scene may have")
    draco("indices_missing", lambda d, e: d["meshes"][0]["primitives"][0].pop("indices"), "without indices")
    draco("components_lie", lambda d, e: d["accessors"][1].update(type="VEC2"), "3 components, its accessor 2")
    draco("attribute_id_past_int", lambda d, e: e["attributes"].update(NORMAL=2**32 + 1), "is out of range")
    draco("view_missing", lambda d, e: e.update(bufferView=3), "has no bufferView, or one that does not exist")
    draco("view_past_buffer", lambda d, e: d["bufferViews"][0].update(byteOffset=100), "reaches past the end")
    draco("mode_points", lambda d, e: d["meshes"][0]["primitives"][0].update(mode=0), "only TRIANGLES")
    draco("same_accessors_twice", lambda d, e: d["meshes"][0]["primitives"].append(
        copy.deepcopy(d["meshes"][0]["primitives"][0])), "", expect="loads")
    draco("accessors_shared_across_streams", lambda d, e: d["bufferViews"].append(dict(d["bufferViews"][0]))
          or d["meshes"][0]["primitives"].append(copy.deepcopy(d["meshes"][0]["primitives"][0]))
          or d["meshes"][0]["primitives"][1]["extensions"]["KHR_draco_mesh_compression"].update(bufferView=1),
          "another Draco stream")
