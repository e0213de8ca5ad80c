"""/api/scenes: upload, list, show, delete, model.glb, debug-ray and bvh."""

import io
import zipfile

import pytest
import rtcore


def upload(client, path, name=None):
    with open(path, "rb") as f:
        return client.post("/api/scenes", files={"file": (name or path.name, f)})


def test_upload_glb_answers_the_scene(client, scenes_dir):
    response = upload(client, scenes_dir / "bunny.glb")
    assert response.status_code == 201, response.text
    info = response.json()
    assert response.headers["location"] == f"/api/scenes/{info['id']}"
    assert info["name"] == "bunny.glb" and info["format"] == "glb"
    assert info["triangle_count"] == rtcore.Scene.load(str(scenes_dir / "bunny.glb")).triangle_count
    assert all(lo < hi for lo, hi in zip(info["bounds_min"], info["bounds_max"]))
    assert len(info["default_camera"]["position"]) == 3
    assert client.get(f"/api/scenes/{info['id']}").json() == info
    assert info["id"] in [s["id"] for s in client.get("/api/scenes").json()["scenes"]]


def test_upload_zip_with_sidecar_reports_lights_and_cameras(client, cornell_zip):
    response = client.post("/api/scenes", files={"file": ("cornell.zip", cornell_zip)})
    assert response.status_code == 201, response.text
    info = response.json()
    assert info["format"] == "obj" and info["triangle_count"] == 32
    assert len(info["lights"]) == 1 and len(info["lights"][0]["position"]) == 3
    assert info["cameras"] and len(info["cameras"][0]["camera"]["target"]) == 3


@pytest.mark.parametrize("name, content, status, words", [
    ("notes.txt", b"hello", 415, ".txt"),
    ("broken.glb", b"glTF\x02\x00\x00\x00\x10\x00\x00\x00garbage!", 400, "broken.glb"),
    ("bad.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", 400, "bad.obj"),
    ("nan.obj", b"v 0 nan 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 400, "nan.obj"),
    ("empty.zip", b"PK\x05\x06" + b"\x00" * 18, 400, "zip"),
])
def test_bad_uploads_are_refused_with_a_reason(client, name, content, status, words):
    before = len(client.get("/api/scenes").json()["scenes"])
    response = client.post("/api/scenes", files={"file": (name, content)})
    assert response.status_code == status, response.text
    assert words in response.json()["detail"]
    assert len(client.get("/api/scenes").json()["scenes"]) == before


def test_upload_without_a_file_is_a_422_naming_it(client):
    response = client.post("/api/scenes", data={"x": "1"})
    assert response.status_code == 422 and "file" in response.json()["detail"]


def test_unknown_scene_is_404_everywhere(client):
    for method, url in [("get", "/api/scenes/nope"), ("delete", "/api/scenes/nope"),
                        ("get", "/api/scenes/nope/model.glb"), ("get", "/api/scenes/nope/bvh?level=0")]:
        response = getattr(client, method)(url)
        assert response.status_code == 404 and "nope" in response.json()["detail"], url
    response = client.post("/api/scenes/nope/debug-ray", json={"pixel": [0, 0]})
    assert response.status_code == 404


def test_model_glb_loads_back_as_the_same_scene(client, cornell_id):
    response = client.get(f"/api/scenes/{cornell_id}/model.glb")
    assert response.status_code == 200 and response.headers["content-type"] == "model/gltf-binary"
    assert response.content[:4] == b"glTF"
    assert rtcore.Scene.from_bytes(response.content, "model.glb").triangle_count == 32


def test_debug_ray_returns_the_ray_tree(client, cornell_id):
    body = {"settings": {"width": 64, "height": 48}, "pixel": [32, 30]}
    response = client.post(f"/api/scenes/{cornell_id}/debug-ray", json=body)
    assert response.status_code == 200, response.text
    path = response.json()
    assert path["pixel_x"] == 32 and path["pixel_y"] == 30
    kinds = [s["kind"] for s in path["segments"]]
    assert kinds[0] == "PRIMARY" and "SHADOW" in kinds
    assert path["segments"][0]["outcome"] == "HIT" and path["segments"][0]["visited_leaves"]


@pytest.mark.parametrize("body, words", [
    ({"settings": {"width": 64, "height": 48}, "pixel": [64, 0]}, "outside"),
    ({"pixel": [1]}, "pixel: needs 2 values"),
    ({"settings": {"maxDepth": 1000}, "pixel": [0, 0]}, "settings.max_depth: 1000 is above the maximum 64"),
    ({"camera": {"position": [0, 0, 0], "target": [0, 0, 0]}, "pixel": [0, 0]}, "position and target must differ"),
    ({"pixel": [0, 0], "colour": 1}, "colour"),
])
def test_debug_ray_refuses_bad_requests(client, cornell_id, body, words):
    response = client.post(f"/api/scenes/{cornell_id}/debug-ray", json=body)
    assert response.status_code == 422, response.text
    assert words in response.json()["detail"]


def test_bvh_levels_and_leaves(client, cornell_id):
    root = client.get(f"/api/scenes/{cornell_id}/bvh?level=0").json()
    assert len(root["bounds"]) == 6 and root["level"] == 0 and root["node_width"] == 8
    assert root["nodes"] == [0] and root["leaf"] == [False] and root["leaf_triangles"] == [32]
    # 32 triangles fit under one 8-wide node: its children are all leaves, one level down.
    assert root["total_levels"] == 2
    level1 = client.get(f"/api/scenes/{cornell_id}/bvh?level=1").json()
    assert 2 <= len(level1["nodes"]) <= root["node_width"] and sum(level1["leaf_triangles"]) == 32
    assert level1["leaf"] == [True] * len(level1["nodes"])
    leaves = client.get(f"/api/scenes/{cornell_id}/bvh?leaves=1").json()
    assert leaves["level"] == -1 and sum(leaves["leaf_triangles"]) == 32
    assert sorted(leaves["nodes"]) == sorted(level1["nodes"]) and all(leaves["leaf"])
    deep = client.get(f"/api/scenes/{cornell_id}/bvh?level={root['total_levels']}")
    assert deep.status_code == 422 and "past the deepest level" in deep.json()["detail"]
    assert client.get(f"/api/scenes/{cornell_id}/bvh?level=-1").status_code == 422


@pytest.fixture(scope="module")
def bunny(client, scenes_dir):
    """The bunny (3,676 triangles) and every level of its tree: leaves sit at several levels."""
    info = upload(client, scenes_dir / "bunny.glb").json()
    root = client.get(f"/api/scenes/{info['id']}/bvh?level=0").json()
    levels = [client.get(f"/api/scenes/{info['id']}/bvh?level={n}").json() for n in range(root["total_levels"])]
    return info, levels, client.get(f"/api/scenes/{info['id']}/bvh?leaves=true").json()


def test_bvh_levels_walk_the_wide_tree(bunny):
    info, levels, leaves = bunny
    width = levels[0]["node_width"]
    assert width == 8 and all(level["node_width"] == width for level in levels)
    assert len(levels) > 2, "a tree several levels deep"
    above = 0  # triangles in the leaves of the levels above
    for n, level in enumerate(levels):
        assert level["level"] == n and len(level["nodes"]) == len(level["leaf"]) == len(level["leaf_triangles"])
        assert len(level["bounds"]) == 6 * len(level["nodes"])
        # Every triangle is under exactly one box of this level or in a leaf above it.
        assert above + sum(level["leaf_triangles"]) == info["triangle_count"], f"level {n}"
        above += sum(t for t, leaf in zip(level["leaf_triangles"], level["leaf"]) if leaf)
        if n:
            inner_above = levels[n - 1]["leaf"].count(False)
            assert 0 < len(level["nodes"]) <= width * inner_above, f"level {n}: at most {width} children per node"
    assert all(levels[-1]["leaf"]), "the deepest level is all leaves"
    assert levels[0]["leaf"] == [False], "the root is a node"
    # One number per box: the nodes are 0..N-1, a leaf's number comes after them.
    inner = [i for level in levels for i, leaf in zip(level["nodes"], level["leaf"]) if not leaf]
    assert sorted(inner) == list(range(len(inner)))
    leaf_numbers = [i for level in levels for i, leaf in zip(level["nodes"], level["leaf"]) if leaf]
    assert min(leaf_numbers) >= len(inner)
    assert sorted(leaf_numbers) == sorted(leaves["nodes"]) and len(set(leaf_numbers)) == len(leaf_numbers)
    assert leaves["leaf"] == [True] * len(leaves["nodes"])
    assert sum(leaves["leaf_triangles"]) == info["triangle_count"]


def test_debug_path_visits_boxes_of_the_tree(client, bunny):
    info, levels, leaves = bunny
    inner = {i for level in levels for i, leaf in zip(level["nodes"], level["leaf"]) if not leaf}
    leaf_triangles = dict(zip(leaves["nodes"], leaves["leaf_triangles"]))
    body = {"settings": {"width": 64, "height": 48}, "pixel": [32, 24]}
    path = client.post(f"/api/scenes/{info['id']}/debug-ray", json=body).json()
    assert path["segments"][0]["outcome"] == "HIT" and path["segments"][0]["visited_leaves"]
    for i, s in enumerate(path["segments"]):
        assert s["visited_nodes"][0] == 0, "every ray starts at the root"
        assert set(s["visited_nodes"]) <= inner, f"segment {i}: visited nodes are the tree's nodes"
        assert set(s["visited_leaves"]) <= leaf_triangles.keys(), f"segment {i}: visited leaves are the tree's leaves"
        tested = sum(leaf_triangles[leaf] for leaf in s["visited_leaves"])
        if s["kind"] == "SHADOW":
            assert s["triangles_tested"] <= tested  # an any-hit query may stop inside a leaf
        else:
            assert s["triangles_tested"] == tested, f"segment {i}: every triangle of the leaves it entered"


def test_delete_removes_the_scene(client, scenes_dir):
    scene_id = upload(client, scenes_dir / "teapot.glb").json()["id"]
    assert client.delete(f"/api/scenes/{scene_id}").status_code == 204
    assert client.get(f"/api/scenes/{scene_id}").status_code == 404
    assert scene_id not in [s["id"] for s in client.get("/api/scenes").json()["scenes"]]


def test_openapi_shows_the_proto_schemas(client):
    schema = client.get("/openapi.json").json()
    settings = schema["components"]["schemas"]["rt.RenderSettings"]["properties"]
    assert settings["width"]["default"] == 640 and settings["max_depth"]["maximum"] == 64
    body = schema["paths"]["/api/jobs"]["post"]["requestBody"]["content"]["application/json"]["schema"]
    assert body == {"$ref": "#/components/schemas/rt.JobRequest"}


def make_zip(files: dict[str, bytes]) -> bytes:
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in files.items():
            z.writestr(name, data)
    return out.getvalue()


def test_a_scene_without_lights_reports_the_default_rig(client):
    obj = b"v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n"
    response = client.post("/api/scenes", files={"file": ("unlit.obj", obj)})
    assert response.status_code == 201, response.text
    info = response.json()
    assert info["light_rig"] is True
    assert [light["kind"] for light in info["lights"]] == ["DIRECTIONAL", "DIRECTIONAL"]
    assert any("default light rig" in w for w in info["warnings"])
