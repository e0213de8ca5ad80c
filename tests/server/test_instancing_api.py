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


def test_moving_instances_render_what_moving_copies_render(client):
    moving = tuple(range(0, NODES, 2))
    ours = upload(client, "moving-shared.gltf", instanced_gltf(NODES, moving=moving))
    theirs = upload(client, "moving-copies.gltf", instanced_gltf(NODES, copies=True, moving=moving))
    settings = {"width": W, "height": H, "samples_per_pixel": 16}
    a = render_color(client, {"scene_id": ours["id"], "camera": CAMERA, "settings": settings})[1]
    b = render_color(client, {"scene_id": theirs["id"], "camera": CAMERA, "settings": settings})[1]
    still = render(client, upload(client, "still.gltf", instanced_gltf(NODES))["id"])
    assert np.abs(a - still).mean() > 5e-3, "the moving nodes blur"
    assert np.abs(a - b).mean() < 1e-3, np.abs(a - b).mean()
    assert (np.abs(a - b) > 0.02).mean() < 0.002


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


def corners(bounds, to_world):
    """A box's eight corners taken to world space by a column-major 4x4."""
    m = np.asarray(to_world, dtype=np.float64).reshape(4, 4).T
    lo, hi = np.asarray(bounds[:3]), np.asarray(bounds[3:])
    points = np.array([[hi[0] if c & 1 else lo[0], hi[1] if c & 2 else lo[1], hi[2] if c & 4 else lo[2], 1.0]
                       for c in range(8)])
    return (points @ m.T)[:, :3]


def test_the_debugger_reaches_the_instance_tree_the_ray_entered(client, shared):
    x, y = W // 2, H // 2
    primary = client.post(f"/api/scenes/{shared['id']}/debug-ray",
                          json={"camera": CAMERA, "settings": {"width": W, "height": H}, "pixel": [x, y]}).json()["segments"][0]
    entered = [t for t in primary["trees"] if t.get("tree") == "BVH_TREE_INSTANCE"]
    assert entered, primary["trees"]
    hit = np.asarray(primary["end"])
    held = []
    for visit in entered:
        tree = client.get(f"/api/scenes/{shared['id']}/bvh?leaves=true&tree={visit.get('instance', 0)}").json()
        assert tree["tree"] == "BVH_TREE_INSTANCE" and tree["instance_count"] == NODES
        assert tree["to_world"] != [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], "an instance's own transform"
        by_id = dict(zip(tree["nodes"], range(len(tree["nodes"]))))
        for leaf in visit["visited_leaves"]:
            assert leaf in by_id, f"leaf {leaf} is not one of instance {visit.get('instance', 0)}'s leaves"
            world = corners(tree["bounds"][6 * by_id[leaf]:6 * by_id[leaf] + 6], tree["to_world"])
            if np.all(hit >= world.min(0) - 1e-3) and np.all(hit <= world.max(0) + 1e-3):
                held.append(tree["instance_name"])
    # The camera aims at node 15, and node 9 stands in front of it on the
    # same line: the tree named for the node that placed it holds the hit.
    # (Two leaves of its tree may meet at the hit point.)
    assert set(held) == {"n9"}, f"only visited leaves of node n9's instance, in world space, hold the hit point: {held}"
    root = client.get(f"/api/scenes/{shared['id']}/bvh?level=0&tree={entered[0].get('instance', 0)}").json()
    assert root["total_levels"] >= 1 and len(root["nodes"]) == 1


@pytest.mark.parametrize("tree", ["nope", "-1", str(NODES), "1e3", "world", " 3", "99999999999"])
def test_a_tree_the_scene_lacks_is_refused(client, shared, tree):
    response = client.get(f"/api/scenes/{shared['id']}/bvh", params={"level": 0, "tree": tree})
    assert 400 <= response.status_code < 500, response.text
    assert "tree" in response.text
