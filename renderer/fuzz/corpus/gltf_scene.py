"""Hostile glTF files about what places things in the scene: node transforms,
cameras, lights, primitives, extensions, the rt extras and animations.

Most of these are numbers out of range (huge, NaN, zero quaternions) that must
be refused with a message, rather than turned into a non-finite world
transform that the renderer would only trip over later.
"""

from __future__ import annotations

import math
import struct

from .bases import TRIANGLE_BIN, Corpus, gltf_case, with_buffer


def scene_cases(c: Corpus) -> None:
    case = gltf_case(c)

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
    for name, ortho, expect, mentions in [
        ("ymag_zero", {"xmag": 1e308, "ymag": 0, "znear": 0, "zfar": -1}, "error", "orthographic.ymag"),
        ("ymag_huge", {"xmag": 1, "ymag": 1e308, "znear": 0, "zfar": 1}, "error", "ortho_height"),
        ("zfar_below_znear", {"xmag": 1, "ymag": 1, "znear": 2, "zfar": 1}, "error", "orthographic.zfar"),
        ("valid", {"xmag": 2, "ymag": 1, "znear": 0, "zfar": 10}, "loads", ""),
    ]:
        case(f"camera_orthographic_{name}", lambda d, o=ortho: d.update(cameras=[{"type": "orthographic",
             "orthographic": o}]) or d["nodes"].append({"camera": 0}) or d["scenes"][0]["nodes"].append(1),
             expect, mentions)
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
    case("requires_spec_gloss", lambda d: d.update(extensionsRequired=["KHR_materials_pbrSpecularGlossiness"]),
         "error", "requires the glTF extension 'KHR_materials_pbrSpecularGlossiness'")
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
