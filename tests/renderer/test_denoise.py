"""Denoising (settings.denoise OIDN) through rtcore: what it buys against a
converged reference, that it is deterministic, and that it leaves the render
it starts from alone."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest
import rtcore

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "renderer" / "bench"))
import accuracy_scenes  # noqa: E402

SIZE = {"width": 320, "height": 240}  # smaller, the network sees too little of the image
# One shadow ray per camera sample: every sample is a whole noisy estimate of
# the pixel (soft shadow and anti-aliasing together), the images a denoiser is
# made for; the reference is the same estimator converged.
NOISY = {"light_samples": 1}
REFERENCE = {"samples_per_pixel": 256, "light_samples": 2}


@pytest.fixture(scope="module")
def scenes(scenes_dir, tmp_path_factory):
    dragon, _ = accuracy_scenes.sphere_lit_glb(scenes_dir / "dragon_2.glb", tmp_path_factory.mktemp("dragon"))
    return {"cornell_sphere_light": scenes_dir / "cornell_sphere_light.obj", "dragon": dragon}


def render(scene, **settings):
    return scene.render(scene.default_camera, json.dumps({**SIZE, **settings}))


def rmse(reference, image):
    return float(np.sqrt(np.mean((image.astype(np.float64) - reference) ** 2)))


@pytest.mark.parametrize("name", ["cornell_sphere_light", "dragon"])
def test_denoised_error_is_lower_than_noisy_error_at_1_4_and_16_samples(scenes, name):
    scene = rtcore.Scene.load(str(scenes[name]))
    reference = render(scene, **REFERENCE)
    for spp in (1, 4, 16):
        noisy = render(scene, samples_per_pixel=spp, **NOISY)
        denoised = render(scene, samples_per_pixel=spp, denoise="OIDN", **NOISY)
        # RMSE, the charts' first measure. Mean HDR-FLIP is lower too at 1 spp,
        # but higher at 16 where the denoiser's blur outweighs the noise it removes.
        assert rmse(reference, denoised) < rmse(reference, noisy), (name, spp)


def test_denoising_is_deterministic_and_starts_from_the_plain_render(scenes):
    scene = rtcore.Scene.load(str(scenes["cornell_sphere_light"]))
    settings = json.dumps({**SIZE, "samples_per_pixel": 4, **NOISY})
    plain = scene.render(scene.default_camera, settings)
    tile = scene.render_tile(scene.default_camera, settings, 0, 0, SIZE["width"], SIZE["height"],
                             aux=["albedo", "normal"])
    # Rendering the guides changes no colour bit.
    assert tile["color"].tobytes() == plain.tobytes()
    first = rtcore.denoise(tile["color"], tile["albedo"], tile["normal"])
    assert first.tobytes() == rtcore.denoise(tile["color"], tile["albedo"], tile["normal"]).tobytes()
    assert first.tobytes() == rtcore.denoise(tile["color"], tile["albedo"], tile["normal"], threads=1).tobytes()
    assert first.tobytes() == render(scene, samples_per_pixel=4, denoise="OIDN", **NOISY).tobytes()
    assert rtcore.denoiser_library().endswith("libOpenImageDenoise.so.2")


def test_a_pixel_that_is_not_finite_stays_where_it_is(scenes):
    scene = rtcore.Scene.load(str(scenes["cornell_sphere_light"]))
    tile = scene.render_tile(scene.default_camera, json.dumps({**SIZE, **NOISY}), 0, 0, SIZE["width"],
                             SIZE["height"], aux=["albedo", "normal"])
    color = tile["color"].copy()
    color[40, 60] = [np.nan, 1.0, 1.0]
    color[10, 10] = [np.inf, 0.0, 0.0]
    out = rtcore.denoise(color, tile["albedo"], tile["normal"])
    assert np.isnan(out[40, 60, 0]) and np.isinf(out[10, 10, 0])
    assert np.isfinite(np.delete(out.reshape(-1, 3), [40 * SIZE["width"] + 60, 10 * SIZE["width"] + 10], 0)).all()
    clean = rtcore.denoise(tile["color"], tile["albedo"], tile["normal"])
    far = np.ones(color.shape[:2], bool)
    far[30:51, 50:71] = far[0:21, 0:21] = False
    assert np.abs(out - clean)[far].max() < 0.05 * clean.max()


def test_bad_arrays_are_refused_by_shape():
    rgb = np.zeros((4, 5, 3), np.float32)
    with pytest.raises(ValueError, match="albedo and normal must have the colour's shape"):
        rtcore.denoise(rgb, np.zeros((4, 4, 3), np.float32), rgb)
    with pytest.raises(ValueError, match=r"denoise\(\): expected an \(height, width, 3\) array"):
        rtcore.denoise(np.zeros((4, 5), np.float32), rgb, rgb)
