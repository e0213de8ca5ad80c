"""Orthographic cameras over REST: a scene's orthographic camera in its
SceneInfo, a job with an orthographic camera renders it (the square keeps its
size whatever the distance), the debugger traces it, and bad values are a 422
naming the field."""
import numpy as np
import pytest
from app.services import layer_files

from ortho_scene import bright_box, ortho_gltf
from stream_reader import wait_for

W, H = 64, 48


@pytest.fixture(scope="module")
def square(client):
    response = client.post("/api/scenes", files={"file": ("square.gltf", ortho_gltf(ymag=1.0).encode())})
    assert response.status_code == 201, response.text
    return response.json()


def ortho_camera(distance=5.0, height=2.0):
    return {"position": [0, 0, distance], "target": [0, 0, 0], "projection": "ORTHOGRAPHIC",
            "ortho_height": height}


def render(client, scene_id, camera):
    body = {"scene_id": scene_id, "camera": camera, "settings": {"width": W, "height": H}}
    response = client.post("/api/jobs", json=body)
    assert response.status_code == 202, response.text
    job = wait_for(client, response.json()["id"])
    assert job["state"] == "DONE", job
    assert job["request"]["camera"]["projection"] == "ORTHOGRAPHIC"
    return layer_files.load(client.app.state.settings.jobs_dir / job["id"], "color")[..., :3]


def test_scene_info_lists_the_orthographic_camera(square):
    cameras = {c["name"]: c["camera"] for c in square["cameras"]}
    assert cameras["plan"]["projection"] == "ORTHOGRAPHIC" and cameras["plan"]["ortho_height"] == 2.0
    assert cameras["eye"].get("projection", "PERSPECTIVE") == "PERSPECTIVE"


def test_an_orthographic_job_renders_at_its_scale_at_any_distance(client, square):
    near = bright_box(render(client, square["id"], ortho_camera(5.0)))
    assert near == (20, 12, 43, 35), "the unit square is half of the 2-unit-tall image, centred"
    assert bright_box(render(client, square["id"], ortho_camera(40.0))) == near
    x0, y0, x1, y1 = bright_box(render(client, square["id"], ortho_camera(5.0, height=4.0)))
    assert (x1 - x0 + 1, y1 - y0 + 1) == (12, 12)


def test_the_debugger_traces_an_orthographic_pixel(client, square):
    response = client.post(f"/api/scenes/{square['id']}/debug-ray",
                           json={"camera": ortho_camera(), "settings": {"width": W, "height": H}, "pixel": [8, 40]})
    assert response.status_code == 200, response.text
    primary = response.json()["segments"][0]
    # Film x, y of the pixel's centre on the 2.667 x 2 image plane at z = 5.
    expected = [((8.5 / W) * 2 - 1) * (W / H), 1 - (40.5 / H) * 2, 5.0]
    np.testing.assert_allclose(primary["origin"], expected, atol=1e-5)


@pytest.mark.parametrize("camera, words", [
    ({"position": [0, 0, 5], "target": [0, 0, 0], "projection": "ORTHOGRAPHIC"},
     "camera.ortho_height: is required for an ORTHOGRAPHIC camera"),
    (ortho_camera(height=0), "camera.ortho_height: 0 is below the minimum 1e-30"),
    (ortho_camera(height=-1), "camera.ortho_height: -1 is below the minimum 1e-30"),
    (ortho_camera(height="NaN"), "camera.ortho_height: must be a finite number"),
    (ortho_camera(height="Infinity"), "camera.ortho_height: must be a finite number"),
    ({**ortho_camera(), "projection": "FISHEYE"}, "FISHEYE"),
])
def test_bad_orthographic_cameras_are_422_naming_the_field(client, square, camera, words):
    response = client.post("/api/jobs", json={"scene_id": square["id"], "camera": camera})
    assert response.status_code == 422, response.text
    assert words in response.json()["detail"]
