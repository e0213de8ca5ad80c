"""Scenes whose nodes share a mesh, over REST: SceneInfo counts the triangles
rays meet, model.glb keeps one mesh drawn by many nodes (and loads back
instanced), a job renders what the same scene with a copy per node renders,
and the debugger traces a ray into an instance and walks the top-level tree."""
import json
import struct

import numpy as np
import pytest
import rtcore

from instanced_scene import instanced_gltf
from stream_reader import render_color

W, H = 64, 48
NODES = 30
CAMERA = {"position": [0, 6, 8], "target": [1.5, 0.8, -5], "up": [0, 1, 0], "fov_y": 60}


def upload(client, name, text):
    response = client.post("/api/scenes", files={"file": (name, text.encode())})
    assert response.status_code == 201, response.text
    return response.json()


@pytest.fixture(scope="module")
def shared(client):
    return upload(client, "shared.gltf", instanced_gltf(NODES))


@pytest.fixture(scope="module")
def copies(client):
    return upload(client, "copies.gltf", instanced_gltf(NODES, copies=True))


def render(client, scene_id):
    return render_color(client, {"scene_id": scene_id, "camera": CAMERA, "settings": {"width": W, "height": H}})[1]


def test_scene_info_counts_every_placed_triangle(shared, copies):
    assert shared["triangle_count"] == copies["triangle_count"] == 8 * NODES
    np.testing.assert_allclose(shared["bounds_min"], copies["bounds_min"], atol=0.5)
    np.testing.assert_allclose(shared["bounds_max"], copies["bounds_max"], atol=0.5)


def glb_json(glb: bytes) -> dict:
    (length,) = struct.unpack_from("<I", glb, 12)
    return json.loads(glb[20:20 + length])


def glb_bin_bytes(glb: bytes) -> int:
    (length,) = struct.unpack_from("<I", glb, 12)
    return struct.unpack_from("<I", glb, 20 + length)[0]


def test_model_glb_keeps_one_mesh_drawn_by_every_node(client, shared, copies):
    glb = client.get(f"/api/scenes/{shared['id']}/model.glb").content
    doc = glb_json(glb)
    assert len(doc["meshes"]) == 1
    drawing = [n for n in doc["nodes"] if n.get("mesh") == 0]
    assert len(drawing) == NODES and all(len(n["matrix"]) == 16 for n in drawing)
    flat = client.get(f"/api/scenes/{copies['id']}/model.glb").content
    # The vertices once, not once per node.
    assert glb_bin_bytes(glb) * 10 < glb_bin_bytes(flat), (glb_bin_bytes(glb), glb_bin_bytes(flat))
    assert rtcore.Scene.from_bytes(glb, "model.glb").triangle_count == 8 * NODES


def test_a_job_renders_what_the_copies_render(client, shared, copies):
    ours, theirs = render(client, shared["id"]), render(client, copies["id"])
    assert ours.max() > 0.05, "the octahedra are lit"
    assert np.abs(ours - theirs).mean() < 1e-3
    assert (np.abs(ours - theirs) > 0.02).mean() < 0.002


def test_the_debugger_follows_a_ray_into_an_instance(client, shared):
    # The camera looks at the centre of node 15's octahedron.
    x, y = W // 2, H // 2
    response = client.post(f"/api/scenes/{shared['id']}/debug-ray",
                           json={"camera": CAMERA, "settings": {"width": W, "height": H}, "pixel": [int(x), int(y)]})
    assert response.status_code == 200, response.text
    primary = response.json()["segments"][0]
    assert primary.get("outcome") == "HIT" or primary.get("outcome") == 1, primary
    assert primary["triangles_tested"] > 0 and primary["visited_nodes"]
    top = client.get(f"/api/scenes/{shared['id']}/bvh?leaves=true")
    assert top.status_code == 200, top.text
    leaves = top.json()
    assert len(leaves["nodes"]) == NODES, "one top-level leaf per instance"
    assert sum(leaves["leaf_triangles"]) == 8 * NODES, "the top level's leaves place every instance"
