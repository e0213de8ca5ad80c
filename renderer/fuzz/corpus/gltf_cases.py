"""Hostile glTF (JSON) files: the largest family, as the JSON form is where a
document can lie about everything (text, graph, data, references, numbers).

The cases are split by theme over gltf_buffers, gltf_materials and gltf_scene;
gltf_cases() keeps them in the order the manifest has always listed them, so
the corpus stays byte-identical whichever module a case lives in. This module
holds the cases about the document itself: its text and its node graph.
"""

from __future__ import annotations

from .bases import Corpus, dump, gltf_case, textured_doc, triangle_doc, truncations
from .gltf_buffers import buffer_cases
from .gltf_materials import material_cases
from .gltf_scene import scene_cases


def gltf_cases(c: Corpus) -> None:
    document_cases(c)
    buffer_cases(c)
    material_cases(c)
    scene_cases(c)


def document_cases(c: Corpus) -> None:
    """Valid bases, text that is not a glTF, deep nesting, and node graphs that cycle or point nowhere."""
    case = gltf_case(c)

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
