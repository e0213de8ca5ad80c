"""The background: what rays that miss see, set by --background / --background-gradient
(rtrender) and the settings' background fields (rtcore), over the scene's own."""
import json
import re
import subprocess

import numpy as np
import pytest
from PIL import Image

import rtcore

# Level, looking down -Z, 90 degrees: row j of 9 looks up by ndc y = 1 - 2 (j + 0.5) / 9.
CAMERA = json.dumps({"position": [0, 0, 0], "target": [0, 0, -1], "fov_y": 90})
SIZE = 9


@pytest.fixture
def empty_view(tmp_path):
    """A scene whose one triangle is behind the camera: every camera ray misses."""
    (tmp_path / "tri.obj").write_text("v -1 -1 10\nv 1 -1 10\nv 0 1 10\nf 1 2 3\n")
    (tmp_path / "cam.json").write_text(CAMERA)
    return tmp_path


def height_of_rows():
    ndc = 1 - 2 * (np.arange(SIZE) + 0.5) / SIZE
    return ndc / np.sqrt(ndc**2 + 1)  # the centre column's unit direction, its y


def srgb8(linear):
    linear = np.clip(np.asarray(linear, dtype=float), 0, 1)
    srgb = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)
    return np.round(srgb * 255)


def run_cli(binary, folder, *args):
    command = [binary, folder / "tri.obj", "-o", folder / "out.png", "--camera-file", folder / "cam.json",
               "--width", SIZE, "--height", SIZE, "--quiet", *args]
    return subprocess.run(list(map(str, command)), capture_output=True, text=True, timeout=120)


def test_cli_background_flags_reach_the_image(rtrender, empty_view):
    result = run_cli(rtrender, empty_view, "--background", "0.1,0.2,0.3")
    assert result.returncode == 0, result.stderr
    image = np.asarray(Image.open(empty_view / "out.png").convert("RGB")).astype(int)
    assert (np.abs(image - srgb8([0.1, 0.2, 0.3])) <= 1).all()

    result = run_cli(rtrender, empty_view, "--background-gradient", "bottom=0,0,0;top=0,0,1")
    assert result.returncode == 0, result.stderr
    blue = np.asarray(Image.open(empty_view / "out.png").convert("RGB")).astype(int)[:, SIZE // 2, 2]
    expected = srgb8(0.5 + 0.5 * height_of_rows())
    assert np.abs(blue - expected).max() <= 1, (blue, expected)


@pytest.mark.parametrize("args, message", [
    (("--background", "0.1,0.2"), "settings.background: needs 3 values, got 2"),
    (("--background", "0.1,-1,0"), r"settings.background\[1\]: -1 is below the minimum 0"),
    (("--background", "0.1,inf,0"), "--background: 'inf' is not a number"),
    (("--background", "0.1,2e6,0"), r"settings.background\[1\]: 2e\+06 is above the maximum 1e\+06"),
    (("--background-gradient", "bottom=0,0,0"), "settings.background_gradient.top: is required"),
    (("--background-gradient", "left=0,0,0"), "--background-gradient: 'left=0,0,0' is not NAME=VALUE"),
    (("--background-gradient", "bottom=0,0,0;top=1,1,1", "--background", "1,1,1"),
     "settings.background_gradient: give background or background_gradient, not both"),
])
def test_cli_bad_backgrounds_exit_2_naming_the_flag_or_field(rtrender, empty_view, args, message):
    result = run_cli(rtrender, empty_view, *args)
    assert result.returncode == 2
    assert re.search(message, result.stderr), result.stderr


def test_rtcore_settings_override_the_sidecar(empty_view):
    (empty_view / "tri.rt.json").write_text(json.dumps({
        "lights": [{"position": [0, 5, 0]}],
        "background_gradient": {"bottom": [1, 0, 0], "horizon": [0, 1, 0], "top": [0, 0, 1]}}))
    scene = rtcore.Scene.load(str(empty_view / "tri.obj"))
    size = {"width": SIZE, "height": SIZE}
    image = scene.render(CAMERA, json.dumps(size))
    y = height_of_rows()
    column = image[:, SIZE // 2, :3]
    up, down = y >= 0, y < 0
    np.testing.assert_allclose(column[up, 1], 1 - y[up], atol=1e-5)  # horizon to top
    np.testing.assert_allclose(column[up, 2], y[up], atol=1e-5)
    np.testing.assert_allclose(column[down, 0], -y[down], atol=1e-5)  # horizon to bottom
    np.testing.assert_allclose(column[down, 2], 0, atol=1e-6)

    solid = scene.render(CAMERA, json.dumps({**size, "background": [0.25, 0.5, 4]}))
    np.testing.assert_allclose(solid[..., :3], np.broadcast_to([0.25, 0.5, 4], (SIZE, SIZE, 3)), atol=1e-6)
    with pytest.raises(ValueError, match=r"settings.background_gradient.horizon: needs 3 values, got 1"):
        scene.render(CAMERA, json.dumps({**size, "background_gradient": {"bottom": [0, 0, 0], "top": [1, 1, 1],
                                                                          "horizon": [1]}}))
