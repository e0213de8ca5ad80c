"""The rtrender command line: outputs, summary line, errors and exit codes."""
import json
import re
import struct
import subprocess
import zlib

import numpy as np
from PIL import Image

import rtcore


def run(rtrender, *args):
    return subprocess.run([str(rtrender), *map(str, args)], capture_output=True, text=True, timeout=300)


def test_help_lists_every_render_setting(rtrender):
    result = run(rtrender, "--help")
    assert result.returncode == 0
    for flag in ("--width", "--height", "--max-depth", "--min-contribution", "--light-samples", "--settings",
                 "--samples-per-pixel", "--adaptive-threshold"):
        assert flag in result.stdout
    assert re.search(r"--pixel-filter NAME +gaussian, box, tent, grid \(default gaussian\)", result.stdout)
    assert re.search(r"--light-sampling NAME +cone, sphere \(default cone\)", result.stdout)
    assert re.search(r"--tone-map NAME +clip, reinhard, aces \(default clip\)", result.stdout)
    assert re.search(r"--bloom-strength N +default 0, 0 to 1\n", result.stdout)


def test_png_matches_rtcore_and_summary_is_printed(rtrender, scenes_dir, tmp_path):
    out = tmp_path / "cornell.png"
    result = run(rtrender, scenes_dir / "cornell.obj", "-o", out, "--width", 64, "--height", 48, "--quiet")
    assert result.returncode == 0, result.stderr
    summary = re.search(r"(\d+) triangles.*BVH (\d+) nodes depth (\d+) \((generic|avx2|avx512) kernels\), build ([\d.]+) ms, "
                        r"render ([\d.]+) ms, ([\d.]+) Mrays/s", result.stdout)
    assert summary, result.stdout
    image = np.asarray(Image.open(out).convert("RGB"))
    assert image.shape == (48, 64, 3)

    scene = rtcore.Scene.load(str(scenes_dir / "cornell.obj"))
    linear = scene.render(scene.default_camera, '{"width": 64, "height": 48}')
    srgb = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * np.clip(linear, 0, 1) ** (1 / 2.4) - 0.055)
    expected = np.round(np.clip(srgb, 0, 1) * 255)
    assert np.abs(image.astype(int) - expected.astype(int)).max() <= 1


def test_sampling_flags_and_samples_per_pixel_in_the_summary(rtrender, scenes_dir, tmp_path):
    scene = scenes_dir / "cornell_sphere_light.obj"
    common = ("-o", tmp_path / "a.png", "--width", 32, "--height", 24, "--quiet")
    result = run(rtrender, scene, *common, "--samples-per-pixel", 16, "--pixel-filter", "Tent",
                 "--light-sampling", "sphere")
    assert result.returncode == 0, result.stderr
    assert ", 16.0 samples/pixel -> " in result.stdout
    assert ", 1.0 samples/pixel -> " in run(rtrender, scene, *common).stdout

    result = run(rtrender, scene, *common, "--samples-per-pixel", 128, "--adaptive-threshold", 0.2,
                 "--light-samples", 1)
    assert result.returncode == 0, result.stderr
    mean = float(re.search(r", ([\d.]+) samples/pixel", result.stdout).group(1))
    assert 32 <= mean < 128

    # Flags override the settings file, enums included (the default's zero value too).
    settings = tmp_path / "settings.json"
    settings.write_text(json.dumps({"pixelFilter": "GRID", "samplesPerPixel": 9}))
    assert run(rtrender, scene, *common, "--settings", settings).returncode == 0
    result = run(rtrender, scene, *common, "--settings", settings, "--samples-per-pixel", 10)
    assert result.returncode == 2 and "GRID takes a square number" in result.stderr
    assert run(rtrender, scene, *common, "--settings", settings, "--samples-per-pixel", 10,
               "--pixel-filter", "gaussian").returncode == 0

    result = run(rtrender, scene, *common, "--pixel-filter", "lanczos")
    assert result.returncode == 2
    assert "--pixel-filter: 'lanczos' is not one of gaussian, box, tent, grid" in result.stderr


def test_exr_and_settings_file(rtrender, scenes_dir, tmp_path):
    settings = tmp_path / "settings.json"
    settings.write_text(json.dumps({"width": 32, "height": 24, "maxDepth": 2}))
    out = tmp_path / "cornell.exr"
    result = run(rtrender, scenes_dir / "cornell.obj", "-o", out, "--settings", settings, "--quiet")
    assert result.returncode == 0, result.stderr
    assert out.read_bytes()[:4] == b"\x76\x2f\x31\x01"  # OpenEXR magic


def test_progress_bar_on_stderr(rtrender, scenes_dir, tmp_path):
    result = run(rtrender, scenes_dir / "cornell.obj", "-o", tmp_path / "a.png", "--width", 64, "--height", 64)
    assert result.returncode == 0
    assert "100%" in result.stderr and "tiles" in result.stderr


def test_debug_pixel_prints_the_ray_tree(rtrender, scenes_dir):
    result = run(rtrender, scenes_dir / "cornell.obj", "--debug-pixel", "20,20", "--width", 40, "--height", 40)
    assert result.returncode == 0, result.stderr
    path = json.loads(result.stdout)
    assert path["segments"][0]["kind"] == "PRIMARY"


def test_errors_name_the_problem(rtrender, scenes_dir, tmp_path):
    cases = [
        ((), 2, "no scene"),
        ((scenes_dir / "cornell.obj",), 2, "no output"),
        ((scenes_dir / "cornell.obj", "-o", tmp_path / "x.png", "--width", 0), 2, "settings.width: 0 is below"),
        ((scenes_dir / "cornell.obj", "-o", tmp_path / "x.png", "--samples-per-pixel", 0), 2,
         "settings.samples_per_pixel: 0 is below the minimum 1"),
        ((scenes_dir / "cornell.obj", "-o", tmp_path / "x.png", "--width", "abc"), 2, "not a number"),
        ((scenes_dir / "cornell.obj", "-o", tmp_path / "x.png", "--bogus", 1), 2, "unknown option --bogus"),
        ((scenes_dir / "cornell.obj", "-o", tmp_path / "x.png", "--camera", "nope"), 2, "no camera 'nope'"),
        ((scenes_dir / "cornell.obj", "-o", tmp_path / "x.bmp", "--width", 8, "--height", 8), 1, "unsupported image"),
        ((tmp_path / "missing.obj", "-o", tmp_path / "x.png"), 1, "missing.obj"),
    ]
    for args, code, message in cases:
        result = run(rtrender, *args)
        assert result.returncode == code, (args, result.stderr)
        assert message in result.stderr, (args, result.stderr)


def exr_channels(path):
    """The channel names in an OpenEXR header (its `channels` attribute)."""
    data = path.read_bytes()
    assert data[:4] == b"\x76\x2f\x31\x01"
    at = 8
    while data[at] != 0:
        name_end = data.index(b"\0", at)
        type_end = data.index(b"\0", name_end + 1)
        size = int.from_bytes(data[type_end + 1:type_end + 5], "little")
        value = data[type_end + 5:type_end + 5 + size]
        if data[at:name_end] == b"channels":
            names, i = [], 0
            while value[i] != 0:
                end = value.index(b"\0", i)
                names.append(value[i:end].decode())
                i = end + 1 + 16  # pixel type, pLinear + reserved, x and y sampling
            return names
        at = type_end + 5 + size
    raise AssertionError("no channels attribute")


def test_aux_outputs_are_extra_exr_channels(rtrender, scenes_dir, tmp_path):
    out = tmp_path / "aux.exr"
    result = run(rtrender, scenes_dir / "cornell.obj", "-o", out, "--width", 32, "--height", 24, "--quiet",
                 "--aux", "depth,normal,albedo,bvh_cost,alpha")
    assert result.returncode == 0, result.stderr
    assert sorted(exr_channels(out)) == sorted(
        ["R", "G", "B", "A", "depth.Z", "normal.X", "normal.Y", "normal.Z", "albedo.R", "albedo.G", "albedo.B",
         "bvh_cost.nodes", "bvh_cost.triangles"])
    plain = tmp_path / "plain.exr"
    assert run(rtrender, scenes_dir / "cornell.obj", "-o", plain, "--width", 32, "--height", 24,
               "--quiet").returncode == 0
    assert sorted(exr_channels(plain)) == ["B", "G", "R"]


def test_aux_outputs_need_an_exr_and_known_names(rtrender, scenes_dir, tmp_path):
    result = run(rtrender, scenes_dir / "cornell.obj", "-o", tmp_path / "x.png", "--aux", "depth")
    assert result.returncode == 2
    assert "--aux" in result.stderr and "must be .exr" in result.stderr
    assert not (tmp_path / "x.png").exists()
    result = run(rtrender, scenes_dir / "cornell.obj", "-o", tmp_path / "x.exr", "--aux", "depth,speed")
    assert result.returncode == 2
    assert "unknown auxiliary output 'speed'" in result.stderr and "bvh_cost" in result.stderr


def test_camera_file_with_a_pose_at_shutter_close_blurs(rtrender, scenes_dir, tmp_path):
    """The 2020 report's look-at shift as a camera file; FRAMES in the settings file is
    the mean of still frames at the centres of the shutter interval's parts."""
    still = {"position": [0, 0.5, 1.87], "target": [0, 0.5, 0], "fovY": 40}
    # 0.125 and the frame times 1/4, 3/4 are exact in binary: the frames' cameras match ours bit for bit.
    moving = {**still, "shutterClose": {"position": [0, 0.5, 1.87], "target": [0.125, 0.5, 0]}}
    settings = tmp_path / "settings.json"
    settings.write_text(json.dumps({"width": 48, "height": 36, "motionBlur": "FRAMES", "motionFrames": 2}))
    images = {}
    for name, camera in (("still", still), ("moving", moving)):
        (tmp_path / f"{name}.json").write_text(json.dumps(camera))
        out = tmp_path / f"{name}.png"
        result = run(rtrender, scenes_dir / "cornell.obj", "-o", out, "--settings", settings,
                     "--camera-file", tmp_path / f"{name}.json", "--quiet")
        assert result.returncode == 0, result.stderr
        images[name] = np.asarray(Image.open(out).convert("RGB")).astype(int)
    assert np.abs(images["moving"] - images["still"]).max() > 50, "the image is blurred"

    scene = rtcore.Scene.load(str(scenes_dir / "cornell.obj"))
    frames = [scene.render(json.dumps({**still, "target": [0.125 * t, 0.5, 0]}), '{"width": 48, "height": 36}')
              for t in (0.25, 0.75)]
    linear = np.mean(frames, axis=0)
    srgb = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * np.clip(linear, 0, 1) ** (1 / 2.4) - 0.055)
    assert np.abs(images["moving"] - np.round(np.clip(srgb, 0, 1) * 255)).max() <= 1

    (tmp_path / "bad.json").write_text(json.dumps({**still, "shutterClose": {"position": [0, 0.5, 1.87],
                                                                             "target": [0, 0.5, 1.87]}}))
    result = run(rtrender, scenes_dir / "cornell.obj", "-o", tmp_path / "bad.png", "--camera-file",
                 tmp_path / "bad.json")
    assert result.returncode == 2 and "camera.shutter_close: position and target must differ" in result.stderr


def read_exr_colour(path):
    """R, G, B of an EXR as rtrender writes it (float channels, ZIP blocks of 16
    scanlines) as an (h, w, 3) float32 array."""
    data = path.read_bytes()
    header, at = {}, 8
    while data[at] != 0:
        name_end = data.index(b"\0", at)
        type_end = data.index(b"\0", name_end + 1)
        size = int.from_bytes(data[type_end + 1:type_end + 5], "little")
        header[data[at:name_end].decode()] = data[type_end + 5:type_end + 5 + size]
        at = type_end + 5 + size
    assert header["compression"] == b"\x03", "ZIP compression"
    x0, y0, x1, y1 = struct.unpack("<4i", header["dataWindow"])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    channels = exr_channels(path)
    image = np.zeros((height, width, len(channels)), np.float32)
    blocks = (height + 15) // 16
    for offset in struct.unpack(f"<{blocks}Q", data[at + 1:at + 1 + 8 * blocks]):
        y, size = struct.unpack("<2i", data[offset:offset + 8])
        packed = np.frombuffer(zlib.decompress(data[offset + 8:offset + 8 + size]), np.uint8)
        # Undo OpenEXR's byte predictor, then the split of even and odd bytes.
        deltas = np.cumsum(packed.astype(np.int64)) - 128 * np.arange(packed.size)
        split = (deltas % 256).astype(np.uint8)
        raw = np.empty_like(split)
        half = (split.size + 1) // 2
        raw[0::2], raw[1::2] = split[:half], split[half:]
        rows = min(16, height - (y - y0))
        lines = np.frombuffer(raw.tobytes(), "<f4").reshape(rows, len(channels), width)
        image[y - y0:y - y0 + rows] = lines.transpose(0, 2, 1)
    return image[..., [channels.index(c) for c in "RGB"]]


def test_bloom_moves_light_in_the_exr_and_changes_the_png(rtrender, scenes_dir, tmp_path):
    scene = scenes_dir / "cornell.obj"
    common = ("--width", 64, "--height", 48, "--quiet")
    bloom = ("--bloom-strength", 0.8, "--bloom-threshold", 0.3, "--bloom-radius", 12)
    for name, flags in (("plain", ()), ("bloom", bloom)):
        for extension in ("exr", "png"):
            result = run(rtrender, scene, "-o", tmp_path / f"{name}.{extension}", *common, *flags)
            assert result.returncode == 0, result.stderr
            assert ("rtrender: bloom " in result.stdout) == (name == "bloom"), result.stdout
            assert re.search(r"^rtrender: write [\d.]+ ms$", result.stdout, re.M), result.stdout
    plain, bloomed = read_exr_colour(tmp_path / "plain.exr"), read_exr_colour(tmp_path / "bloom.exr")
    assert plain.shape == (48, 64, 3) and plain.max() > 0.3
    assert np.abs(bloomed - plain).max() > 0.01, "the glow shows in the linear image"
    np.testing.assert_allclose(bloomed.sum(axis=(0, 1), dtype=np.float64), plain.sum(axis=(0, 1), dtype=np.float64),
                               rtol=1e-5)
    png_plain = np.asarray(Image.open(tmp_path / "plain.png"))
    png_bloom = np.asarray(Image.open(tmp_path / "bloom.png"))
    assert not np.array_equal(png_plain, png_bloom)
    # The PNG is the EXR through the display transform: exposure and tone map change it, the EXR not.
    np.testing.assert_array_equal(rtcore.encode_srgb8(bloomed)[..., :3], png_bloom)
    shown = tmp_path / "shown.png"
    result = run(rtrender, scene, "-o", shown, *common, *bloom, "--exposure", -1, "--tone-map", "reinhard")
    assert result.returncode == 0, result.stderr
    np.testing.assert_array_equal(np.asarray(Image.open(shown)),
                                  rtcore.encode_srgb8(bloomed, '{"exposure": -1, "toneMap": "REINHARD"}')[..., :3])


def test_denoise_writes_the_denoised_image_and_with_noisy_the_one_before(rtrender, scenes_dir, tmp_path):
    scene = scenes_dir / "cornell_sphere_light.obj"
    common = ("--width", 64, "--height", 48, "--samples-per-pixel", 2, "--light-samples", 1, "--quiet")
    plain = run(rtrender, scene, "-o", tmp_path / "plain.exr", *common)
    assert plain.returncode == 0, plain.stderr
    assert "rtrender: denoise" not in plain.stdout
    result = run(rtrender, scene, "-o", tmp_path / "denoised.exr", "--noisy", tmp_path / "noisy.exr",
                 "--denoise", "oidn", "--aux", "depth", *common)
    assert result.returncode == 0, result.stderr
    assert re.search(r"^rtrender: denoise [\d.]+ ms \(.*libOpenImageDenoise\.so\.2\)$", result.stdout, re.M), result.stdout
    # The guides are rendered, not written: only the layers asked for are.
    assert exr_channels(tmp_path / "denoised.exr") == ["B", "G", "R", "depth.Z"]
    noisy = read_exr_colour(tmp_path / "noisy.exr")
    assert noisy.tobytes() == read_exr_colour(tmp_path / "plain.exr").tobytes(), "the render is the same without"
    denoised = read_exr_colour(tmp_path / "denoised.exr")
    assert not np.array_equal(denoised, noisy)
    scene_ = rtcore.Scene.load(str(scene))
    settings = '{"width": 64, "height": 48, "samplesPerPixel": 2, "lightSamples": 1, "denoise": "OIDN"}'
    assert denoised.tobytes() == scene_.render(scene_.default_camera, settings).tobytes(), "rtcore denoises alike"


def test_noisy_needs_denoise_and_an_image_file(rtrender, scenes_dir, tmp_path):
    scene = scenes_dir / "cornell.obj"
    without = run(rtrender, scene, "-o", tmp_path / "a.png", "--noisy", tmp_path / "b.png", "--width", 8, "--height", 8)
    assert without.returncode == 2 and "--noisy is the image before denoising" in without.stderr
    assert not (tmp_path / "a.png").exists()
    wrong = run(rtrender, scene, "-o", tmp_path / "a.png", "--noisy", tmp_path / "b.tif", "--denoise", "oidn")
    assert wrong.returncode == 2 and "--noisy: the file must be .png or .exr" in wrong.stderr
    unknown = run(rtrender, scene, "-o", tmp_path / "a.png", "--denoise", "neural")
    assert unknown.returncode == 2 and "no_denoiser, oidn" in unknown.stderr


def test_settings_under_which_glass_would_never_finish_exit_2(rtrender, tmp_path):
    (tmp_path / "glass.mtl").write_text("newmtl glass\nKd 0 0 0\nNi 1.5\nd 0.1\nillum 7\n")
    scene = tmp_path / "pane.obj"
    scene.write_text("mtllib glass.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl glass\nf 1 2 3\n")
    common = ("-o", tmp_path / "pane.png", "--width", 8, "--height", 8, "--max-depth", 64)
    result = run(rtrender, scene, *common, "--min-contribution", 0)
    assert result.returncode == 2, result.stderr
    assert "settings.max_depth: 64 with settings.min_contribution 0 lets one camera ray split" in result.stderr
    assert run(rtrender, scene, *common).returncode == 0
