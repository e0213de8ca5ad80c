"""The feature assets of docs/gltf.md rendered through rtcore: what each one
shows must be what its feature means."""
import sys
from pathlib import Path

import numpy as np
import pytest

import rtcore
from rt import render_pb2

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "renderer" / "samples"))
from glb import with_json  # noqa: E402


def render(scene, **fields) -> np.ndarray:
    settings = render_pb2.RenderSettings(width=96, height=72, **fields).SerializeToString()
    return scene.render(scene.default_camera, settings, threads=2)


@pytest.fixture(scope="module")
def emission(assets_dir):
    return rtcore.Scene.load(str(assets_dir / "emission.glb"))


def test_emission_is_seen_and_bloom_picks_it_up(emission):
    dark = render(emission, light_rig=render_pb2.NO_RIG)
    # Lit by nothing, the sign shows its emission only: the checker's bright
    # cells (strength 4 × the texture) and black ones.
    assert dark.max() > 2.0, "emissive texels above 1 (strength 4) are seen directly"
    bloom = render_pb2.RenderSettings(width=96, height=72, bloom_strength=0.5, bloom_threshold=1.0)
    bloomed = rtcore.apply_bloom(np.ascontiguousarray(dark), bloom.SerializeToString())
    outside = dark.max(axis=2) == 0.0
    assert outside.sum() > 0.3 * outside.size, "the sign leaves some background"
    # Bloom spreads the emitted light over what was black around it.
    assert bloomed[outside].max() > 0.01
    assert bloomed[outside].mean() > 10 * dark[outside].mean() + 1e-4


def test_masked_texels_are_holes_in_the_image_and_the_shadow(assets_dir, tmp_path):
    scene = rtcore.Scene.load(str(assets_dir / "alpha_modes.glb"))
    lit = render(scene)
    # The same file with the mask off: the leaf's quad is a full square.
    path = tmp_path / "alpha_modes_opaque.glb"
    path.write_bytes(with_json((assets_dir / "alpha_modes.glb").read_bytes(),
                               lambda doc: doc["materials"][0].pop("alphaMode")))
    square = render(rtcore.Scene.load(str(path)))
    # The mask removes part of the quad from the image and of its shadow:
    # the masked render is brighter wherever the two differ, never darker.
    difference = lit.sum(axis=2) - square.sum(axis=2)
    assert (difference > 0.05).sum() > 50, "the masked corners of the quad are holes"
    assert (difference < -0.05).sum() < 0.01 * difference.size


def test_the_webp_product_model_renders_as_the_png_one(assets_dir):
    # gltf-transform webp --lossless: the same texels in another container.
    png = rtcore.Scene.load(str(assets_dir / "product.glb"))
    webp = rtcore.Scene.load(str(assets_dir / "product_webp.glb"))
    reference = render(png)
    assert reference.max() > 0.1
    np.testing.assert_array_equal(render(webp), reference)
