"""Hostile sidecars: the <scene>.rt.json beside a scene that adds what the
format cannot say (lights, spheres, cameras, a background, motions, ...).

A sidecar is written by hand, so it is where typos and wrong types land: these
cases give fields wrong types, numbers out of range and names the scene does
not have, beside an OBJ and beside a glTF whose nodes the motions move.
"""

from __future__ import annotations

import json
import math

from .bases import TRI, TRIANGLE_BIN, Corpus, dump, glb, glb_doc, obj, triangle_doc, truncations

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

    def gradient(**stops) -> bytes:
        solid_free = {k: v for k, v in VALID_SIDECAR.items() if k != "background"}
        return json.dumps({**solid_free, "background_gradient": stops}).encode()
    case("gradient_valid", gradient(bottom=[0, 0, 0], horizon=[1, 1, 1], top=[0, 0, 1]), "loads")
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
        ("background_huge", changed(background=[0, 0, 1e7]), "maximum"),
        ("background_and_gradient", changed(background_gradient={"bottom": [0, 0, 0], "top": [1, 1, 1]}), "not both"),
        ("gradient_no_top", gradient(bottom=[0, 0, 0]), "background_gradient.top"),
        ("gradient_negative", gradient(bottom=[0, -1, 0], top=[1, 1, 1]), "background_gradient.bottom"),
        ("gradient_nan", gradient(bottom=[0, 0, 0], top=[1, "NaN", 1]), "finite"),
        ("gradient_horizon_2", gradient(bottom=[0, 0, 0], top=[1, 1, 1], horizon=[1, 1]), "horizon"),
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
