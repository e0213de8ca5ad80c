"""Orthographic cameras through rtrender and rtcore: a glTF scene's
orthographic camera by name, the --orthographic and --perspective overrides,
their errors, and the camera as SceneInfo and Scene.complete give it."""
import subprocess

import numpy as np
import pytest
from PIL import Image

import rtcore
from rt import debug_pb2, job_pb2, render_pb2
from ortho_scene import bright_box, ortho_gltf


def run(rtrender, *args):
    return subprocess.run([str(rtrender), *map(str, args)], capture_output=True, text=True, timeout=120)


@pytest.fixture
def scene_file(tmp_path):
    path = tmp_path / "square.gltf"
    path.write_text(ortho_gltf(ymag=1.0, distance=5.0))
    return path


def square_box(path):
    return bright_box(np.asarray(Image.open(path).convert("RGB")), threshold=20)


def test_scene_ortho_camera_renders_the_square_at_its_scale(rtrender, scene_file, tmp_path):
    # ymag 1: the image is 2 units tall, so the unit square is half of its 48 rows.
    result = run(rtrender, scene_file, "-o", tmp_path / "plan.png", "--camera", "plan",
                 "--width", 64, "--height", 48, "--quiet")
    assert result.returncode == 0, result.stderr
    x0, y0, x1, y1 = square_box(tmp_path / "plan.png")
    assert (x1 - x0 + 1, y1 - y0 + 1) == (24, 24)
    assert (x0, y0) == (20, 12), "centred"

    # The same camera from five times as far: the same square.
    far = tmp_path / "far.gltf"
    far.write_text(ortho_gltf(ymag=1.0, distance=25.0))
    assert run(rtrender, far, "-o", tmp_path / "far.png", "--camera", "plan",
               "--width", 64, "--height", 48, "--quiet").returncode == 0
    assert square_box(tmp_path / "far.png") == (x0, y0, x1, y1)


def test_projection_flags_override_the_chosen_camera(rtrender, scene_file, tmp_path):
    common = ("--width", 64, "--height", 48, "--quiet")
    # Four units tall: the square is 12 rows.
    assert run(rtrender, scene_file, "-o", tmp_path / "o.png", "--camera", "eye", "--orthographic", 4,
               *common).returncode == 0
    x0, y0, x1, y1 = square_box(tmp_path / "o.png")
    assert (x1 - x0 + 1, y1 - y0 + 1) == (12, 12)
    # The ortho camera as a pinhole with its default 45 degrees: 1 / (2 * 5 * tan 22.5°) of 48 rows.
    assert run(rtrender, scene_file, "-o", tmp_path / "p.png", "--camera", "plan", "--perspective",
               *common).returncode == 0
    x0, y0, x1, y1 = square_box(tmp_path / "p.png")
    assert abs((y1 - y0 + 1) - 48 / (10 * np.tan(np.radians(22.5)))) <= 1.5


def test_help_names_the_projection_flags(rtrender):
    result = run(rtrender, "--help")
    assert "--orthographic HEIGHT" in result.stdout and "--perspective" in result.stdout


@pytest.mark.parametrize("args, message", [
    (("--orthographic", 0), "--orthographic: HEIGHT must be a positive finite number, not 0"),
    (("--orthographic", -3), "--orthographic: HEIGHT must be a positive finite number, not -3"),
    (("--orthographic", "inf"), "--orthographic"),
    (("--orthographic", "wide"), "--orthographic"),
    (("--orthographic", 2, "--perspective"), "--orthographic and --perspective exclude each other"),
])
def test_bad_projection_flags_exit_2(rtrender, scene_file, tmp_path, args, message):
    result = run(rtrender, scene_file, "-o", tmp_path / "x.png", *args, "--quiet")
    assert result.returncode == 2
    assert message in result.stderr


def test_camera_file_without_ortho_height_is_refused(rtrender, scene_file, tmp_path):
    camera = tmp_path / "camera.json"
    camera.write_text('{"position": [0, 0, 5], "target": [0, 0, 0], "projection": "ORTHOGRAPHIC"}')
    result = run(rtrender, scene_file, "-o", tmp_path / "x.png", "--camera-file", camera, "--quiet")
    assert result.returncode != 0
    assert "camera.ortho_height: is required for an ORTHOGRAPHIC camera" in result.stderr


def test_scene_info_lists_the_ortho_camera(scene_file):
    scene = rtcore.Scene.load(str(scene_file))
    info = job_pb2.SceneInfo.FromString(scene.info)
    cameras = {c.name: c.camera for c in info.cameras}
    assert cameras["plan"].projection == render_pb2.ORTHOGRAPHIC and cameras["plan"].ortho_height == 2.0
    assert cameras["eye"].projection == render_pb2.PERSPECTIVE


def test_rtcore_renders_and_debugs_the_ortho_camera(scene_file):
    scene = rtcore.Scene.load(str(scene_file))
    camera = render_pb2.Camera(position=[0, 0, 5], target=[0, 0, 0], projection=render_pb2.ORTHOGRAPHIC,
                               ortho_height=2.0).SerializeToString()
    settings = '{"width": 64, "height": 48}'
    image = scene.render(camera, settings)
    assert bright_box(image) == (20, 12, 43, 35)
    # The debugger's primary ray leaves from the pixel's place on the image plane, along -z.
    path = debug_pb2.DebugPath.FromString(scene.debug_path(camera, settings, 8, 40))
    primary = path.segments[0]
    film = ((8.5 / 64) * 2 - 1) * (2.0 * 64 / 48) / 2, (1 - (40.5 / 48) * 2) * 1.0
    np.testing.assert_allclose(primary.origin, [film[0], film[1], 5.0], atol=1e-5)
    assert primary.end[0] == pytest.approx(primary.origin[0]) and primary.end[1] == pytest.approx(primary.origin[1])


@pytest.mark.parametrize("camera, message", [
    ('{"position": [0, 0, 5], "target": [0, 0, 0], "projection": "ORTHOGRAPHIC"}',
     r"^camera\.ortho_height: is required for an ORTHOGRAPHIC camera$"),
    ('{"position": [0, 0, 5], "target": [0, 0, 0], "projection": "ORTHOGRAPHIC", "orthoHeight": 0}',
     r"^camera\.ortho_height: 0 is below the minimum 1e-30$"),
    ('{"position": [0, 0, 5], "target": [0, 0, 0], "projection": "ORTHOGRAPHIC", "orthoHeight": "Infinity"}',
     r"^camera\.ortho_height: must be a finite number$"),
])
def test_complete_refuses_bad_ortho_cameras(scene_file, camera, message):
    scene = rtcore.Scene.load(str(scene_file))
    with pytest.raises(ValueError, match=message):
        scene.complete("rt.JobRequest", '{"camera": %s}' % camera)
