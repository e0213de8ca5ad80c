"""The Cornell box as OBJ + MTL + <stem>.rt.json (rt.SceneExtras).

A unit box (x and z in [-0.5, 0.5], y in [0, 1]) open towards +Z: white floor,
ceiling and back wall, red left wall, green right wall, a short and a tall box,
and a mirror panel on the red wall (MTL illum 3, Ks 0.9). 32 triangles. Every
face carries its own normal, so no vertex normal is smoothed across an edge.

The moving variant makes the short box an object of its own that slides and
turns while the shutter is open (an rt.NodeMotion), and adds a camera that
moves as the 2020 report's did: its look-at point shifted along x.
"""

from __future__ import annotations

import json
import math
import re

import numpy as np

MATERIALS = {
    # name: (Kd, Ks, Ns, illum)
    "white": ((0.73, 0.73, 0.73), (0.0, 0.0, 0.0), 10, 1),
    "red": ((0.63, 0.065, 0.05), (0.0, 0.0, 0.0), 10, 1),
    "green": ((0.14, 0.45, 0.091), (0.0, 0.0, 0.0), 10, 1),
    "box": ((0.73, 0.73, 0.73), (0.05, 0.05, 0.05), 20, 2),
    "mirror": ((0.02, 0.02, 0.02), (0.9, 0.9, 0.9), 1000, 3),
}

LIGHT_POSITION = (0.0, 0.88, 0.25)
# The floor below the light gets an irradiance of about 2.6 (white walls
# nearer the light saturate above that).
LIGHT_INTENSITY = 2.0
SPHERE_LIGHT_RADIUS = 0.1

# The short box at shutter close, in world space: turned by -20 degrees about
# +Y (through the floor's centre), then moved right, clear of the walls.
SHORT_BOX_MOTION = {"node": "short_box", "translation": [0.1, 0.0, 0.05],
                    "rotation": [0.0, math.sin(math.radians(-10)), 0.0, math.cos(math.radians(-10))]}
# The 2020 report's 16 frames shifted the look-at point by 0.01 each: 0.15
# from the first to the last.
LOOK_SHIFT = 0.15

CAMERAS = [
    ("default", {"position": [0.0, 0.5, 1.87], "target": [0.0, 0.5, 0.0],
                 "up": [0.0, 1.0, 0.0], "fov_y": 40.0}),
    # From the front right, facing the mirror on the red wall.
    ("mirror", {"position": [0.3, 0.4, 1.3], "target": [-0.5, 0.45, -0.05],
                "up": [0.0, 1.0, 0.0], "fov_y": 50.0}),
]


def _quad(corners, normal) -> list[tuple]:
    """A quad as two triangles wound counter-clockwise around `normal`."""
    c = [np.asarray(p, float) for p in corners]
    if np.dot(np.cross(c[1] - c[0], c[2] - c[0]), normal) < 0:
        c = c[::-1]
    return [(c, np.asarray(normal, float) / np.linalg.norm(normal))]


def _box(centre_x: float, centre_z: float, size, angle_deg: float) -> list[tuple]:
    """The four sides and the top of a box standing on the floor, turned about Y."""
    w, h, d = (s / 2 for s in size)
    a = math.radians(angle_deg)
    rot = np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])
    centre = np.array([centre_x, 0.0, centre_z])

    def p(x, y, z):
        return rot @ np.array([x, y, z]) + centre

    faces = []
    for axis, sign in ((0, 1), (0, -1), (2, 1), (2, -1)):
        n = np.zeros(3)
        n[axis] = sign
        if axis == 0:
            corners = [p(sign * w, 0, -d), p(sign * w, 0, d), p(sign * w, 2 * h, d), p(sign * w, 2 * h, -d)]
        else:
            corners = [p(-w, 0, sign * d), p(w, 0, sign * d), p(w, 2 * h, sign * d), p(-w, 2 * h, sign * d)]
        faces += _quad(corners, rot @ n)
    faces += _quad([p(-w, 2 * h, -d), p(w, 2 * h, -d), p(w, 2 * h, d), p(-w, 2 * h, d)], (0, 1, 0))
    return faces


def _short_box() -> list[tuple]:
    return _box(0.17, 0.12, (0.3, 0.3, 0.3), -17.0)  # front right


def _tall_box() -> list[tuple]:
    return _box(-0.17, -0.17, (0.3, 0.6, 0.3), 17.0)  # back left


def geometry() -> dict[str, list[tuple]]:
    """Quads (corners, normal) by material."""
    lo, hi = -0.5, 0.5
    return {
        "white": (_quad([(lo, 0, lo), (lo, 0, hi), (hi, 0, hi), (hi, 0, lo)], (0, 1, 0))      # floor
                  + _quad([(lo, 1, lo), (hi, 1, lo), (hi, 1, hi), (lo, 1, hi)], (0, -1, 0))   # ceiling
                  + _quad([(lo, 0, lo), (hi, 0, lo), (hi, 1, lo), (lo, 1, lo)], (0, 0, 1))),  # back
        "red": _quad([(lo, 0, lo), (lo, 1, lo), (lo, 1, hi), (lo, 0, hi)], (1, 0, 0)),
        "green": _quad([(hi, 0, lo), (hi, 0, hi), (hi, 1, hi), (hi, 1, lo)], (-1, 0, 0)),
        "box": _short_box() + _tall_box(),
        # A panel just off the red wall, which the default camera sees at a
        # slant: it mirrors the green wall and the boxes. (On the back wall it
        # would mostly mirror the black outside through the open front.)
        "mirror": _quad([(lo + 0.003, 0.12, -0.38), (lo + 0.003, 0.12, 0.3),
                         (lo + 0.003, 0.85, 0.3), (lo + 0.003, 0.85, -0.38)], (1, 0, 0)),
    }


def _fmt(values) -> str:
    return " ".join(f"{float(v):.6g}" for v in values)


def objects(moving: bool) -> list[tuple[str, str, list[tuple]]]:
    """(object name, material, quads) in file order; each material one object,
    but for the moving short box."""
    parts = [(material, material, quads) for material, quads in geometry().items()]
    if moving:
        parts = [p for p in parts if p[0] != "box"] + [("tall_box", "box", _tall_box()),
                                                       ("short_box", "box", _short_box())]
    return parts


def obj_text(stem: str, moving: bool = False) -> tuple[str, int]:
    lines = [f"# Cornell box for rt (generated by make_samples.py)", f"mtllib {stem}.mtl"]
    vertex = normal = triangles = 0
    for name, material, quads in objects(moving):
        lines += [f"o {name}", f"usemtl {material}"]
        for corners, n in quads:
            lines += [f"v {_fmt(c)}" for c in corners] + [f"vn {_fmt(n)}"]
            v, normal = vertex + 1, normal + 1
            lines.append(f"f {v}//{normal} {v + 1}//{normal} {v + 2}//{normal}")
            lines.append(f"f {v}//{normal} {v + 2}//{normal} {v + 3}//{normal}")
            vertex += 4
            triangles += 2
    return "\n".join(lines) + "\n", triangles


def mtl_text() -> str:
    lines = ["# Cornell box materials; illum 3 makes the mirror trace reflections"]
    for name, (kd, ks, ns, illum) in MATERIALS.items():
        lines += [f"newmtl {name}", f"Ka 0 0 0", f"Kd {_fmt(kd)}", f"Ks {_fmt(ks)}",
                  f"Ns {ns}", f"illum {illum}", ""]
    return "\n".join(lines)


def extras_json(light_radius: float, moving: bool = False) -> str:
    cameras = list(CAMERAS)
    if moving:
        still = dict(CAMERAS[0][1])
        close = {k: still[k] for k in ("position", "target", "up")}
        close["target"] = [still["target"][0] + LOOK_SHIFT, *still["target"][1:]]
        cameras.append(("look_shift", {**still, "shutter_close": close}))
    extras = {
        "lights": [{"position": list(LIGHT_POSITION), "color": [1.0, 1.0, 1.0],
                    "intensity": LIGHT_INTENSITY, "radius": light_radius}],
        "background": [0.0, 0.0, 0.0],
        "cameras": [{"name": name, "camera": camera} for name, camera in cameras],
    }
    if moving:
        extras["motions"] = [SHORT_BOX_MOTION]
    text = json.dumps(extras, indent=2)
    # Each list of numbers on one line.
    return re.sub(r"\[\s+([^\[\]{}\"]*?)\s+\]",
                  lambda m: "[" + ", ".join(v.strip() for v in m.group(1).split(",")) + "]",
                  text) + "\n"


def scene_files(stem: str, light_radius: float, moving: bool = False) -> tuple[dict[str, bytes], int]:
    obj, triangles = obj_text(stem, moving)
    files = {f"{stem}.obj": obj.encode(), f"{stem}.mtl": mtl_text().encode(),
             f"{stem}.rt.json": extras_json(light_radius, moving).encode()}
    return files, triangles
