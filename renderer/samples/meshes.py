"""Meshes for the sample scenes: procedural ones with analytic normals, the npm
packages' models, and the helpers that place a model on the ground."""

from __future__ import annotations

import json
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ply import ListValues, read_ply_mesh, triangulate


@dataclass
class Mesh:
    positions: np.ndarray            # (n, 3) float32
    triangles: np.ndarray            # (m, 3) uint32
    normals: np.ndarray | None = None  # (n, 3) float32, unit length

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        return self.positions.min(axis=0).astype(float), self.positions.max(axis=0).astype(float)


def _mesh(positions, triangles, normals=None) -> Mesh:
    return Mesh(np.asarray(positions, np.float32), np.asarray(triangles, np.uint32),
                None if normals is None else np.asarray(normals, np.float32))


def uv_sphere(radius: float, segments: int, rings: int) -> Mesh:
    """A sphere of `segments` longitudes and `rings` latitude bands with one
    vertex at each pole: 2 * segments * (rings - 1) triangles."""
    theta = np.linspace(0.0, np.pi, rings + 1)[1:-1]           # inner latitudes
    phi = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(t) * np.cos(p), np.cos(t), -np.sin(t) * np.sin(p)], -1).reshape(-1, 3)
    normals = np.concatenate([[[0, 1, 0]], ring, [[0, -1, 0]]])
    top, bottom = 0, len(normals) - 1

    def vid(r, s):
        return 1 + r * segments + s % segments

    tris = []
    for s in range(segments):
        tris.append((top, vid(0, s), vid(0, s + 1)))
        tris.append((bottom, vid(rings - 2, s + 1), vid(rings - 2, s)))
        for r in range(rings - 2):
            a, b, c, d = vid(r, s), vid(r + 1, s), vid(r + 1, s + 1), vid(r, s + 1)
            tris += [(a, b, c), (a, c, d)]
    return _mesh(normals * radius, tris, normals)


def torus(major: float, minor: float, major_segments: int, minor_segments: int) -> Mesh:
    """A torus around +Y: 2 * major_segments * minor_segments triangles."""
    u = np.linspace(0.0, 2.0 * np.pi, major_segments, endpoint=False)
    v = np.linspace(0.0, 2.0 * np.pi, minor_segments, endpoint=False)
    uu, vv = np.meshgrid(u, v, indexing="ij")
    normals = np.stack([np.cos(vv) * np.cos(uu), np.sin(vv), np.cos(vv) * np.sin(uu)], -1)
    centre = np.stack([major * np.cos(uu), np.zeros_like(uu), major * np.sin(uu)], -1)
    positions = (centre + minor * normals).reshape(-1, 3)
    i = np.arange(major_segments)[:, None]
    j = np.arange(minor_segments)[None, :]
    a = i * minor_segments + j
    b = ((i + 1) % major_segments) * minor_segments + j
    c = ((i + 1) % major_segments) * minor_segments + (j + 1) % minor_segments
    d = i * minor_segments + (j + 1) % minor_segments
    tris = np.concatenate([np.stack([a, d, c], -1).reshape(-1, 3),
                           np.stack([a, c, b], -1).reshape(-1, 3)])
    return _mesh(positions, tris, normals.reshape(-1, 3))


def ground(centre_xz, size: float, height: float) -> Mesh:
    """A square of side `size` at y = height facing +Y: two triangles."""
    x, z, h = float(centre_xz[0]), float(centre_xz[1]), size / 2
    positions = [(x - h, height, z - h), (x - h, height, z + h),
                 (x + h, height, z + h), (x + h, height, z - h)]
    return _mesh(positions, [(0, 1, 2), (0, 2, 3)], [(0, 1, 0)] * 4)


def facing_fraction(mesh: Mesh) -> float:
    """Share of triangles whose winding (counter-clockwise = front) agrees with
    their vertex normals; 1.0 for a consistently wound mesh."""
    p = mesh.positions[mesh.triangles].astype(np.float64)
    face = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    n = mesh.normals[mesh.triangles].sum(axis=1)
    return float(np.mean(np.einsum("ij,ij->i", face, n) > 0))


def load_js_mesh(module_dir: Path) -> Mesh:
    """An npm module exporting {positions: [[x,y,z]...], cells: [[i,j,k]...]},
    read through node so any CommonJS form of the export works."""
    script = "process.stdout.write(JSON.stringify(require(process.argv[1])))"
    out = subprocess.run(["node", "-e", script, str(module_dir.resolve())],
                         check=True, capture_output=True, text=True).stdout
    data = json.loads(out)
    positions = np.asarray(data["positions"], np.float64)
    if positions.ndim != 2 or positions.shape[1] != 3 or not np.all(np.isfinite(positions)):
        raise ValueError(f"{module_dir}: positions are not finite [x, y, z] triples")
    cells = data["cells"]
    counts = np.fromiter((len(c) for c in cells), np.int64, len(cells))
    flat = np.fromiter((i for c in cells for i in c), np.int64, int(counts.sum()))
    tris = triangulate(ListValues(counts, flat))
    if tris.size and (tris.min() < 0 or tris.max() >= len(positions)):
        raise ValueError(f"{module_dir}: cell index out of range")
    return weld(_mesh(positions, tris))


def weld(mesh: Mesh) -> Mesh:
    """Merge vertices at identical positions, so normals computed from the faces
    are smooth across the seams between separately modelled patches (the
    teapot's Bezier patches each have their own border vertices)."""
    unique, inverse = np.unique(mesh.positions, axis=0, return_inverse=True)
    return Mesh(unique, inverse.reshape(-1)[mesh.triangles].astype(np.uint32))


def load_ply(path: Path) -> Mesh:
    positions, triangles = read_ply_mesh(path)
    return Mesh(positions, triangles)


def place_on_ground(mesh: Mesh, size: float = 1.0) -> Mesh:
    """Scale so the largest extent is `size`, centre on x and z, rest on y = 0."""
    lo, hi = mesh.bounds
    scale = size / float(np.max(hi - lo))
    offset = -np.array([(lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2])
    positions = ((mesh.positions.astype(np.float64) + offset) * scale).astype(np.float32)
    return Mesh(positions, mesh.triangles, mesh.normals)
