"""The background over REST: settings.background and settings.background_gradient reach
the render and win over the scene's sidecar; bad values are a 422 naming the field;
model.glb carries the scene's own background for the 3D view."""

import io
import json
import struct
import zipfile

import numpy as np
import pytest

from stream_reader import render_color

SIZE = 9
# Level, looking down -Z, 90 degrees: every ray misses the triangle behind the camera.
CAMERA = {"position": [0, 0, 0], "target": [0, 0, -1], "fov_y": 90}
SIDECAR = {"lights": [{"position": [0, 5, 0]}], "background": [0.5, 0.25, 0.125]}


@pytest.fixture(scope="module")
def empty_view_id(client):
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as z:
        z.writestr("tri.obj", "v -1 -1 10\nv 1 -1 10\nv 0 1 10\nf 1 2 3\n")
        z.writestr("tri.rt.json", json.dumps(SIDECAR))
    response = client.post("/api/scenes", files={"file": ("tri.zip", out.getvalue())})
    assert response.status_code == 201, response.text
    return response.json()["id"]


def render(client, scene_id, **settings):
    body = {"scene_id": scene_id, "camera": CAMERA, "settings": {"width": SIZE, "height": SIZE, **settings}}
    return render_color(client, body)[1]


def test_the_sidecars_background_unless_the_settings_give_one(client, empty_view_id):
    np.testing.assert_allclose(render(client, empty_view_id), np.broadcast_to(SIDECAR["background"], (SIZE, SIZE, 3)))
    solid = render(client, empty_view_id, background=[0, 2, 0])
    np.testing.assert_allclose(solid, np.broadcast_to([0, 2, 0], (SIZE, SIZE, 3)))

    image = render(client, empty_view_id, background_gradient={"bottom": [0, 0, 0], "top": [0, 0, 1]})
    ndc = 1 - 2 * (np.arange(SIZE) + 0.5) / SIZE
    height = ndc / np.sqrt(ndc**2 + 1)  # the centre column's unit directions, their y
    np.testing.assert_allclose(image[:, SIZE // 2, 2], 0.5 + 0.5 * height, atol=1e-5)
    assert (np.diff(image[:, 0, 2]) < 0).all(), "bluer towards the top of the image"


@pytest.mark.parametrize("settings, words", [
    ({"background": [0, -1, 0]}, "settings.background[1]: -1 is below the minimum 0"),
    ({"background": [0, "NaN", 0]}, "settings.background[1]: must be a finite number"),
    ({"background": [0, 0, 1e7]}, "settings.background[2]: 1e+07 is above the maximum 1e+06"),
    ({"background": [1, 1]}, "settings.background: needs 3 values, got 2"),
    ({"background_gradient": {"top": [1, 1, 1]}}, "settings.background_gradient.bottom: is required"),
    ({"background_gradient": {"bottom": [0, 0, 0], "top": [1, 1, 1], "horizon": [2, 2, -2]}},
     "settings.background_gradient.horizon[2]: -2 is below the minimum 0"),
    ({"background": [1, 1, 1], "background_gradient": {"bottom": [0, 0, 0], "top": [1, 1, 1]}},
     "settings.background_gradient: give background or background_gradient, not both"),
])
def test_bad_backgrounds_are_a_422_naming_the_field(client, empty_view_id, settings, words):
    response = client.post("/api/jobs", json={"scene_id": empty_view_id, "settings": settings})
    assert response.status_code == 422
    assert words in response.json()["detail"]


def glb_json(glb: bytes) -> dict:
    (length,) = struct.unpack_from("<I", glb, 12)
    return json.loads(glb[20:20 + length])


def test_model_glb_carries_the_scenes_background(client, empty_view_id):
    response = client.get(f"/api/scenes/{empty_view_id}/model.glb")
    assert response.status_code == 200
    extras = glb_json(response.content)["scenes"][0]["extras"]
    assert extras["rt"]["background"] == SIDECAR["background"]
    assert "rt_default_rig" not in extras, "the scene has a light of its own"
