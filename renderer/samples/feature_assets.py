"""Small glTF files, one per feature docs/gltf.md lists as supported or
approximated: each exercises its feature and little else, so the table's test
(tests/renderer/test_gltf_compatibility.py) and the three.js peer check can
load them by name.

Every image is made here from numbers (no binary is committed): checkers,
gradients and a leaf-shaped mask, encoded with Pillow.

This module has the materials, textures, samplers, image formats and lights,
and the helpers every asset is built from; the assets about how a file is put
together (primitive modes, external and inline data, the node graph, skins,
morph targets, animation, cameras) are in structure_assets.py, and
make_assets.py lists both in one table.
"""

from __future__ import annotations

import io

import numpy as np
from PIL import Image

from glb import GlbBuilder, look_at_quaternion

# A unit quad in the XY plane facing +Z, texture v down the image as glTF has it.
QUAD_POSITIONS = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
QUAD_NORMALS = np.tile(np.array([0, 0, 1], np.float32), (4, 1))
QUAD_UVS = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)
QUAD_TRIANGLES = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)


def encode(pixels: np.ndarray, fmt: str = "PNG") -> bytes:
    """uint8 H×W×C pixels as an image file."""
    mode = {1: "L", 2: "LA", 3: "RGB", 4: "RGBA"}[pixels.shape[2] if pixels.ndim == 3 else 1]
    buffer = io.BytesIO()
    image = Image.fromarray(pixels if pixels.ndim == 2 or pixels.shape[2] > 1 else pixels[..., 0], mode)
    image.save(buffer, fmt, **({"lossless": True} if fmt == "WEBP" else {}))
    return buffer.getvalue()


def checker(size: int = 64, cells: int = 8, a=(230, 60, 40), b=(40, 90, 220)) -> np.ndarray:
    y, x = np.mgrid[0:size, 0:size] * cells // size
    pick = ((x + y) % 2).astype(bool)[..., None]
    return np.where(pick, np.array(a, np.uint8), np.array(b, np.uint8)).astype(np.uint8)


def leaf_mask(size: int = 128) -> np.ndarray:
    """Alpha of a leaf: a lens between two circles, with a stem."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size * 2.0 - 1.0
    lens = (x - 0.55) ** 2 + y ** 2 < 1.0
    lens &= (x + 0.55) ** 2 + y ** 2 < 1.0
    stem = (np.abs(x) < 0.04) & (y > 0.6)
    return np.where(lens | stem, 255, 0).astype(np.uint8)


def floor(builder: GlbBuilder, material: int, size: float = 3.0, y: float = -1.0) -> None:
    positions = np.array([[-size, y, -size], [size, y, -size], [size, y, size], [-size, y, size]], np.float32)
    normals = np.tile(np.array([0, 1, 0], np.float32), (4, 1))
    builder.mesh("floor", positions, np.array([[0, 2, 1], [0, 3, 2]]), material, normals)


def quad(builder: GlbBuilder, name: str, material: int, offset=(0.0, 0.0, 0.0), **attributes) -> int:
    attributes.setdefault("TEXCOORD_0", QUAD_UVS)
    return builder.mesh(name, QUAD_POSITIONS + np.asarray(offset, np.float32), QUAD_TRIANGLES, material,
                        QUAD_NORMALS, attributes)


def textured(builder: GlbBuilder, pixels: np.ndarray, fmt: str = "PNG", sampler: dict | None = None) -> int:
    mime = {"PNG": "image/png", "JPEG": "image/jpeg", "WEBP": "image/webp"}[fmt]
    return builder.texture(builder.image(encode(pixels, fmt), mime), sampler)


def pbr(base=(1.0, 1.0, 1.0, 1.0), metallic=0.0, roughness=0.8, **fields) -> dict:
    return {"pbrMetallicRoughness": {"baseColorFactor": list(base), "metallicFactor": metallic,
                                     "roughnessFactor": roughness}, **fields}


def with_texture(material: dict, slot: str, info: dict) -> dict:
    material["pbrMetallicRoughness"][slot] = info
    return material


def texture_transform() -> bytes:
    """A checker shifted, scaled and turned by KHR_texture_transform, and a second
    quad reading its checker through TEXCOORD_1."""
    b = GlbBuilder("rt feature_assets.py")
    texture = textured(b, checker())
    transform = {"offset": [0.25, 0.1], "scale": [2.0, 1.5], "rotation": 0.4}
    b.use_extension("KHR_texture_transform")
    moved = b.add_material(with_texture(pbr(), "baseColorTexture", {
        "index": texture, "extensions": {"KHR_texture_transform": transform}}))
    second = b.add_material(with_texture(pbr(), "baseColorTexture", {"index": texture, "texCoord": 1}))
    quad(b, "transformed", moved, (-1.1, 0, 0))
    quad(b, "second_uv_set", second, (1.1, 0, 0), TEXCOORD_1=QUAD_UVS[:, ::-1] * 3.0)
    return b.to_bytes()


def vertex_colors() -> bytes:
    b = GlbBuilder("rt feature_assets.py")
    colors = np.array([[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 0, 1]], np.float32)
    quad(b, "coloured", b.add_material(pbr()), COLOR_0=colors)
    return b.to_bytes()


def alpha_modes() -> bytes:
    """A leaf-masked quad (MASK) and a half see-through one (BLEND) over a floor."""
    b = GlbBuilder("rt feature_assets.py")
    mask = leaf_mask()
    leaf = np.dstack([np.full_like(mask, 60), np.full_like(mask, 170), np.full_like(mask, 50), mask])
    leaf_texture = textured(b, leaf)
    masked = b.add_material(with_texture(pbr(alphaMode="MASK", alphaCutoff=0.5, doubleSided=True),
                                         "baseColorTexture", {"index": leaf_texture}))
    blended = b.add_material(pbr((0.9, 0.2, 0.2, 0.4), alphaMode="BLEND"))
    quad(b, "leaf", masked, (-1.1, 0.2, 0))
    quad(b, "glass_pane", blended, (1.1, 0.2, 0))
    floor(b, b.add_material(pbr((0.8, 0.8, 0.8, 1.0))))
    return b.to_bytes()


def emission() -> bytes:
    b = GlbBuilder("rt feature_assets.py")
    b.use_extension("KHR_materials_emissive_strength")
    texture = textured(b, checker(a=(255, 200, 80), b=(0, 0, 0)))
    glowing = b.add_material(pbr((0.1, 0.1, 0.1, 1.0), emissiveFactor=[1.0, 1.0, 1.0],
                                 emissiveTexture={"index": texture},
                                 extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}))
    quad(b, "sign", glowing)
    return b.to_bytes()


def metallic_roughness() -> bytes:
    """Metallic in B and roughness in G of one map, and an occlusion map in R."""
    b = GlbBuilder("rt feature_assets.py")
    ramp = np.linspace(0, 255, 64).astype(np.uint8)
    mr = np.dstack([np.zeros((64, 64), np.uint8), np.tile(ramp, (64, 1)), np.tile(ramp[:, None], (1, 64))])
    occlusion = checker(a=(255, 255, 255), b=(90, 90, 90))
    material = with_texture(pbr((0.9, 0.6, 0.2, 1.0), 1.0, 1.0, occlusionTexture={"index": textured(b, occlusion)}),
                            "metallicRoughnessTexture", {"index": textured(b, mr)})
    quad(b, "brushed", b.add_material(material))
    return b.to_bytes()


def normal_map() -> bytes:
    """Bumps in a tangent-space normal map; the file has no tangents, so the
    renderer makes them with MikkTSpace."""
    b = GlbBuilder("rt feature_assets.py")
    y, x = (np.mgrid[0:128, 0:128] + 0.5) / 128 * 2 * np.pi * 4
    n = np.dstack([0.5 * np.cos(x), 0.5 * np.cos(y), np.ones_like(x)])
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    pixels = np.round((n * 0.5 + 0.5) * 255).astype(np.uint8)
    material = pbr((0.7, 0.7, 0.75, 1.0), normalTexture={"index": textured(b, pixels), "scale": 1.0})
    quad(b, "bumpy", b.add_material(material))
    return b.to_bytes()


def double_sided() -> bytes:
    b = GlbBuilder("rt feature_assets.py")
    quad(b, "one_sided", b.add_material(pbr((0.2, 0.8, 0.2, 1.0))), (-1.1, 0, 0))
    quad(b, "two_sided", b.add_material(pbr((0.8, 0.2, 0.8, 1.0), doubleSided=True)), (1.1, 0, 0))
    return b.to_bytes()


def samplers() -> bytes:
    """UVs past [0, 1] through CLAMP_TO_EDGE and MIRRORED_REPEAT samplers."""
    b = GlbBuilder("rt feature_assets.py")
    uvs = QUAD_UVS * 3.0 - 1.0
    for i, (s, t) in enumerate([(33071, 33071), (33648, 33648)]):
        texture = textured(b, checker(cells=2), sampler={"wrapS": s, "wrapT": t})
        material = b.add_material(with_texture(pbr(), "baseColorTexture", {"index": texture}))
        quad(b, f"wrap_{s}", material, (-1.1 + 2.2 * i, 0, 0), TEXCOORD_0=uvs)
    return b.to_bytes()


def image_formats() -> bytes:
    """The same checker as PNG, JPEG and EXT_texture_webp WebP (with a PNG fallback)."""
    b = GlbBuilder("rt feature_assets.py")
    b.use_extension("EXT_texture_webp")
    pixels = checker()
    for i, fmt in enumerate(["PNG", "JPEG", "WEBP"]):
        texture = textured(b, pixels, fmt)
        if fmt == "WEBP":
            record = b.gltf["textures"][texture]
            record["extensions"] = {"EXT_texture_webp": {"source": record["source"]}}
            record["source"] = b.image(encode(pixels, "PNG"))
        material = b.add_material(with_texture(pbr(), "baseColorTexture", {"index": texture}))
        quad(b, fmt.lower(), material, (-2.2 + 2.2 * i, 0, 0))
    return b.to_bytes()


def lights() -> bytes:
    """A point, a spot and a directional light over a floor."""
    b = GlbBuilder("rt feature_assets.py")
    floor(b, b.add_material(pbr((0.8, 0.8, 0.8, 1.0))))
    quad(b, "card", b.add_material(pbr((0.8, 0.3, 0.3, 1.0))))
    b.point_light("lamp", (0.0, 2.0, 2.0), 20.0)
    ext = b.gltf["extensions"]["KHR_lights_punctual"]["lights"]
    ext.append({"type": "spot", "intensity": 40.0, "range": 10.0,
                "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}})
    b._node({"name": "spot", "translation": [2.0, 2.0, 2.0], "extensions": {
        "KHR_lights_punctual": {"light": 1}}, "rotation": look_at_quaternion((2.0, 2.0, 2.0), (0.0, 0.0, 0.0))})
    ext.append({"type": "directional", "intensity": 2.0, "color": [1.0, 0.9, 0.8]})
    b._node({"name": "sun", "rotation": look_at_quaternion((0.0, 1.0, 1.0), (0.0, 0.0, 0.0)), "extensions": {
        "KHR_lights_punctual": {"light": 2}}})
    return b.to_bytes()


def transmission() -> bytes:
    b = GlbBuilder("rt feature_assets.py")
    b.use_extension("KHR_materials_transmission")
    b.use_extension("KHR_materials_ior")
    glass = b.add_material(pbr((1.0, 1.0, 1.0, 1.0), 0.0, 0.0, extensions={
        "KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.45}}))
    quad(b, "glass", glass)
    floor(b, b.add_material(pbr((0.8, 0.8, 0.8, 1.0))))
    return b.to_bytes()


def unlit() -> bytes:
    """A KHR_materials_unlit checker card over a lit floor."""
    b = GlbBuilder("rt feature_assets.py")
    b.use_extension("KHR_materials_unlit")
    texture = textured(b, checker())
    card = b.add_material(with_texture(pbr(extensions={"KHR_materials_unlit": {}}), "baseColorTexture",
                                       {"index": texture}))
    quad(b, "card", card)
    floor(b, b.add_material(pbr((0.8, 0.8, 0.8, 1.0))))
    return b.to_bytes()


def normal_map_tangents() -> bytes:
    """The normal-mapped quad with its tangents in the file."""
    doc_builder = GlbBuilder("rt feature_assets.py")
    y, x = (np.mgrid[0:64, 0:64] + 0.5) / 64 * 2 * np.pi * 2
    n = np.dstack([0.4 * np.cos(x), np.zeros_like(x), np.ones_like(x)])
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    texture = textured(doc_builder, np.round((n * 0.5 + 0.5) * 255).astype(np.uint8))
    material = doc_builder.add_material(pbr((0.7, 0.7, 0.75, 1.0), normalTexture={"index": texture}))
    tangents = np.tile(np.array([1, 0, 0, 1], np.float32), (4, 1))
    quad(doc_builder, "bumpy", material, TANGENT=tangents)
    return doc_builder.to_bytes()
