"""A model that looks like what users upload from a product pipeline: a table
lantern with PBR texture maps, a normal map, an emissive band and an
alpha-masked perforated shade, and no lights (so it renders under the default
rig, as most downloaded models do).

The maps are procedural, at any size: 512² for the tests, 4096² for the
memory report (tests/renderer/test_texture_memory.py).
"""

from __future__ import annotations

import numpy as np

from feature_assets import encode
from glb import GlbBuilder


def lathe(profile: np.ndarray, segments: int) -> tuple[np.ndarray, ...]:
    """The surface swept by (radius, height) points around +Y: positions,
    normals, UVs (u around, v along the profile) and triangles. The seam
    column is duplicated so u runs 0..1 without wrapping."""
    r, h = profile[:, 0], profile[:, 1]
    angle = np.linspace(0.0, 2.0 * np.pi, segments + 1)
    ca, sa = np.cos(angle)[None, :], np.sin(angle)[None, :]
    grid = (len(profile), segments + 1)
    positions = np.stack([r[:, None] * ca, np.broadcast_to(h[:, None], grid), r[:, None] * sa], axis=-1)
    # The profile's outward normal is its tangent turned a quarter.
    dr, dh = np.gradient(r), np.gradient(h)
    length = np.hypot(dr, dh)
    nr, nh = dh / length, -dr / length
    normals = np.stack([nr[:, None] * ca, np.broadcast_to(nh[:, None], grid), nr[:, None] * sa], axis=-1)
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(r), np.diff(h)))])
    u, v = np.meshgrid(np.linspace(0.0, 1.0, segments + 1), arc / arc[-1])
    uvs = np.stack([u, v], axis=-1)
    rows, cols = len(profile), segments + 1
    i, j = np.mgrid[0:rows - 1, 0:cols - 1]
    a, b = i * cols + j, i * cols + j + 1
    c, d = (i + 1) * cols + j + 1, (i + 1) * cols + j
    triangles = np.concatenate([np.stack([a, c, b], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    return (positions.reshape(-1, 3).astype(np.float32), normals.reshape(-1, 3).astype(np.float32),
            uvs.reshape(-1, 2).astype(np.float32), triangles.astype(np.uint32))


def maps(size: int) -> dict[str, np.ndarray]:
    """Base colour, metallic-roughness, normal, occlusion and emission maps of
    the body: knurled metal bands on a painted body."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    band = (y > 0.08) & (y < 0.18)
    paint = np.array([38, 70, 64], np.float32)
    brass = np.array([200, 160, 90], np.float32)
    grain = 0.9 + 0.1 * np.sin(x * 2 * np.pi * 180 + 3 * np.sin(y * 40))
    base = np.where(band[..., None], brass * grain[..., None], paint * (0.95 + 0.05 * grain[..., None]))
    metal = np.where(band, 255, 0)
    rough = np.where(band, 70, 150 + 40 * (grain - 0.9) * 10)
    mr = np.dstack([np.zeros_like(metal), rough, metal])
    # Knurling on the band: a diamond height field, differentiated into normals.
    phase = 2 * np.pi * 60
    dx = np.where(band, 0.6 * np.cos(phase * (x + y)) + 0.6 * np.cos(phase * (x - y)), 0.0)
    dy = np.where(band, 0.6 * np.cos(phase * (x + y)) - 0.6 * np.cos(phase * (x - y)), 0.0)
    n = np.dstack([-dx, -dy, np.ones_like(dx)])
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    occlusion = np.where(band, 255 - 40 * (1 + np.cos(phase * (x + y))) / 2, 255)
    glow = (y > 0.85) & (y < 0.9)
    emission = np.where(glow[..., None], np.array([255, 190, 110]), 0)
    as_bytes = lambda a: np.clip(np.round(a), 0, 255).astype(np.uint8)  # noqa: E731
    return {"base": as_bytes(base), "mr": as_bytes(mr), "normal": as_bytes((n * 0.5 + 0.5) * 255),
            "occlusion": as_bytes(np.dstack([occlusion] * 3)), "emission": as_bytes(emission)}


def perforation(size: int) -> np.ndarray:
    """RGBA of the shade: opaque cream with round holes that MASK cuts out."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    cell_x, cell_y = (x * 48) % 1.0 - 0.5, (y * 16) % 1.0 - 0.5
    holes = cell_x ** 2 + cell_y ** 2 < 0.3 ** 2
    rgba = np.empty((size, size, 4), np.uint8)
    rgba[..., :3] = (235, 225, 200)
    # Holes at alpha 1/255, not 0: still far under the cutoff, and lossless WebP
    # keeps the colour of a texel that is not fully transparent, so the WebP
    # copy filters exactly like the PNG at the holes' rims.
    rgba[..., 3] = np.where(holes, 1, 255)
    return rgba


def product_model(map_size: int = 512) -> bytes:
    b = GlbBuilder("rt product_model.py")
    m = maps(map_size)
    texture = {name: b.texture(b.image(encode(pixels))) for name, pixels in m.items()}
    b.use_extension("KHR_materials_emissive_strength")
    body = b.add_material({
        "name": "body",
        "pbrMetallicRoughness": {"baseColorTexture": {"index": texture["base"]},
                                 "metallicRoughnessTexture": {"index": texture["mr"]}},
        "normalTexture": {"index": texture["normal"], "scale": 1.0},
        "occlusionTexture": {"index": texture["occlusion"]},
        "emissiveTexture": {"index": texture["emission"]}, "emissiveFactor": [1.0, 1.0, 1.0],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3.0}}})
    shade = b.add_material({
        "name": "perforated_shade", "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True,
        "pbrMetallicRoughness": {"baseColorTexture": {"index": b.texture(b.image(encode(perforation(map_size))))},
                                 "metallicFactor": 0.0, "roughnessFactor": 0.9}})
    bulb = b.add_material({"name": "bulb", "emissiveFactor": [1.0, 0.85, 0.6],
                           "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 6.0}},
                           "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0}})

    t = np.linspace(0.0, 1.0, 40)
    body_profile = np.stack([0.35 + 0.12 * np.sin(np.pi * t) - 0.2 * t ** 3, 0.9 * t], axis=1)
    body_profile = np.concatenate([[[0.001, 0.0]], body_profile, [[0.001, 0.9]]])
    shade_profile = np.stack([0.28 + 0.22 * t, 0.9 + 0.5 * t], axis=1)
    s = np.linspace(-np.pi / 2, np.pi / 2, 16)
    bulb_profile = np.stack([0.12 * np.cos(s) + 1e-3, 1.05 + 0.12 * np.sin(s)], axis=1)
    for name, profile, material in [("body", body_profile, body), ("shade", shade_profile, shade),
                                    ("bulb", bulb_profile, bulb)]:
        positions, normals, uvs, triangles = lathe(profile, 96)
        b.mesh(name, positions, triangles, material, normals, {"TEXCOORD_0": uvs})
    return b.to_bytes()
