"""The rtcore module: loading, tiles, batch ray queries, debugger exports."""
import json
import os
import re
import subprocess
import threading

import numpy as np
import pytest
from PIL import Image

import rtcore
from rt import debug_pb2, job_pb2, render_pb2, scene_pb2


@pytest.fixture(scope="module")
def cornell(scenes_dir):
    return rtcore.Scene.load(str(scenes_dir / "cornell.obj"))


def settings(width=48, height=36, **fields):
    return render_pb2.RenderSettings(width=width, height=height, **fields).SerializeToString()


def scene_info(scene) -> job_pb2.SceneInfo:
    return job_pb2.SceneInfo.FromString(scene.info)


def named_camera(scene, name: str) -> bytes:
    return next(c.camera for c in scene_info(scene).cameras if c.name == name).SerializeToString()


def test_load_reports_the_scene(cornell):
    info = scene_info(cornell)
    assert cornell.triangle_count == info.triangle_count >= 30
    lo, hi = info.bounds_min, info.bounds_max
    assert all(a < b for a, b in zip(lo, hi))
    assert info.cameras, "the sample Cornell box names a camera"
    camera = info.cameras[0].camera
    assert len(camera.position) == 3 and len(camera.target) == 3
    assert info.default_camera.SerializeToString() == cornell.default_camera
    assert len(info.lights) == 1 and not info.light_rig
    stats = cornell.bvh_stats
    assert stats["triangles"] == cornell.triangle_count and stats["nodes"] >= 1


def test_tiles_assemble_into_the_full_image(cornell):
    camera = cornell.default_camera
    full = cornell.render(camera, settings(), threads=2, tile_size=16)
    assert full.shape == (36, 48, 3) and full.dtype == np.float32
    assert full.max() > 0.05, "the lit box is not black"
    assembled = np.zeros_like(full)
    for y in range(0, 36, 10):
        for x in range(0, 48, 13):
            w, h = min(13, 48 - x), min(10, 36 - y)
            assembled[y:y + h, x:x + w] = cornell.render_tile(camera, settings(), x, y, w, h)
    np.testing.assert_array_equal(assembled, full)


def test_settings_and_camera_accept_json(cornell):
    camera_json = json.dumps({"position": [0, 1, 3.5], "target": [0, 1, 0], "up": [0, 1, 0], "fov_y": 40})
    from_json = cornell.render_tile(camera_json, '{"width": 16, "height": 12}', 0, 0, 16, 12)
    camera = render_pb2.Camera(position=[0, 1, 3.5], target=[0, 1, 0], up=[0, 1, 0], fov_y=40)
    from_bytes = cornell.render_tile(camera.SerializeToString(), settings(16, 12), 0, 0, 16, 12)
    np.testing.assert_array_equal(from_json, from_bytes)


def test_bad_settings_name_the_field(cornell):
    with pytest.raises(ValueError, match=r"settings\.width: 0 is below the minimum 1"):
        cornell.render_tile(cornell.default_camera, settings(width=0), 0, 0, 1, 1)
    with pytest.raises(ValueError, match="widht"):
        cornell.render_tile(cornell.default_camera, '{"widht": 3}', 0, 0, 1, 1)
    with pytest.raises(ValueError, match="not inside"):
        cornell.render_tile(cornell.default_camera, settings(8, 8), 4, 4, 8, 8)
    with pytest.raises(ValueError, match="camera"):
        cornell.render_tile(b"\xff\xff", settings(8, 8), 0, 0, 1, 1)


def test_missing_scene_is_a_clear_error(tmp_path):
    with pytest.raises(ValueError, match="nope.obj"):
        rtcore.Scene.load(str(tmp_path / "nope.obj"))


def test_batch_queries_agree_with_each_other(cornell):
    rng = np.random.default_rng(1)
    info = scene_info(cornell)
    lo, hi = (np.array(b, dtype=np.float32) for b in (info.bounds_min, info.bounds_max))
    origins = (lo + (hi - lo) * rng.random((5000, 3))).astype(np.float32)
    targets = (lo + (hi - lo) * rng.random((5000, 3))).astype(np.float32)
    directions = targets - origins
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    t, primitive, u, v = cornell.intersect(origins, directions)
    hit = primitive >= 0
    assert hit.mean() > 0.5, "rays between points inside a closed box mostly hit"
    assert np.all(np.isinf(t[~hit]))
    assert np.all((u[hit] >= 0) & (v[hit] >= 0) & (u[hit] + v[hit] <= 1.0001))
    t_max = np.full(5000, 0.5, dtype=np.float32)
    blocked = cornell.occluded(origins, directions, t_max)
    np.testing.assert_array_equal(blocked, hit & (t < 0.5))


def test_batch_queries_refuse_bad_arrays(cornell):
    with pytest.raises(ValueError, match="rows"):
        cornell.intersect(np.zeros((3, 3), np.float32), np.ones((2, 3), np.float32))
    with pytest.raises(ValueError, match="finite"):
        cornell.intersect(np.full((1, 3), np.nan, np.float32), np.ones((1, 3), np.float32))
    with pytest.raises(TypeError):
        cornell.intersect(np.zeros((3, 2), np.float32), np.ones((3, 2), np.float32))


def test_debug_path_records_the_ray_tree(cornell):
    path = debug_pb2.DebugPath.FromString(cornell.debug_path(cornell.default_camera, settings(), 24, 18))
    assert (path.pixel_x, path.pixel_y) == (24, 18)
    primary = path.segments[0]
    assert primary.kind == debug_pb2.PRIMARY and primary.outcome == debug_pb2.HIT and primary.parent == -1
    assert len(primary.origin) == 3 and len(primary.end) == 3 and len(primary.normal) == 3
    assert primary.visited_nodes and primary.visited_leaves, "the traversal is recorded"
    shadows = [s for s in path.segments if s.kind == debug_pb2.SHADOW]
    assert shadows and all(s.outcome in (debug_pb2.OCCLUDED, debug_pb2.REACHED_LIGHT) for s in shadows)
    assert all(0 <= s.parent < len(path.segments) for s in path.segments[1:])
    # The recorded path and the rendered pixel are the same computation.
    pixel = cornell.render_tile(cornell.default_camera, settings(), 24, 18, 1, 1)[0, 0]
    np.testing.assert_allclose(path.color, pixel, rtol=1e-6)


def test_bvh_boxes_cover_the_scene(cornell):
    root = debug_pb2.BvhBoxes.FromString(cornell.bvh_boxes(0))
    assert root.level == 0 and len(root.nodes) == 1 and len(root.bounds) == 6
    assert root.leaf_triangles[0] == cornell.triangle_count and list(root.leaf) == [False]
    assert root.node_width == 8
    leaves = debug_pb2.BvhBoxes.FromString(cornell.bvh_boxes(-1))
    assert leaves.level == -1 and sum(leaves.leaf_triangles) == cornell.triangle_count
    assert len(leaves.bounds) == 6 * len(leaves.nodes) and list(leaves.leaf) == [True] * len(leaves.nodes)
    assert len(leaves.nodes) == cornell.bvh_stats["leaves"]
    assert root.total_levels == cornell.bvh_stats["depth"] + 1
    # Every level's boxes: at most node_width children per node above, all nodes and leaves once.
    levels = [debug_pb2.BvhBoxes.FromString(cornell.bvh_boxes(n)) for n in range(root.total_levels)]
    for above, level in zip(levels, levels[1:]):
        assert len(level.nodes) <= root.node_width * list(above.leaf).count(False)
    assert sum(list(level.leaf).count(False) for level in levels) == cornell.bvh_stats["nodes"]
    assert sorted(n for level in levels for n, leaf in zip(level.nodes, level.leaf) if leaf) == sorted(leaves.nodes)


def test_bvh_cost_counts_what_the_debugger_records(scenes_dir):
    # The BVH_COST layer and the debugger count the same traversal: wide nodes
    # whose child boxes were tested, triangles in the leaf blocks tested.
    bunny = rtcore.Scene.load(str(scenes_dir / "bunny.glb"))
    camera = bunny.default_camera
    cost = bunny.render_tile(camera, settings(), 0, 0, 48, 36, aux=["bvh_cost"])["bvh_cost"]
    for x, y in [(24, 18), (20, 20), (30, 12), (0, 0)]:
        path = debug_pb2.DebugPath.FromString(bunny.debug_path(camera, settings(), x, y))
        nodes = sum(len(s.visited_nodes) for s in path.segments)
        triangles = sum(s.triangles_tested for s in path.segments)
        assert list(cost[y, x]) == [nodes, triangles], f"pixel ({x}, {y})"


def test_glb_loads_from_bytes(scenes_dir):
    data = (scenes_dir / "bunny.glb").read_bytes()
    scene = rtcore.Scene.from_bytes(data, "bunny.glb")
    assert scene.triangle_count == rtcore.Scene.load(str(scenes_dir / "bunny.glb")).triangle_count > 3000
    with pytest.raises(ValueError):
        rtcore.Scene.from_bytes(data[:100], "bunny.glb")


def test_messages_quoting_bytes_that_are_not_utf8_stay_readable(tmp_path):
    # A loader message quotes the file; Python must get it as text (ValueError,
    # not UnicodeDecodeError), and warnings likewise.
    obj = b"mtllib \xff\xfe.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
    with pytest.raises(ValueError, match=r"^x\.obj: mtllib '\?\?\.mtl' names another file") as error:
        rtcore.Scene.from_bytes(obj, "x.obj")
    assert not isinstance(error.value, UnicodeDecodeError)
    (tmp_path / "x.obj").write_bytes(obj)
    assert "x.obj: material library '??.mtl' not found" in scene_info(rtcore.Scene.load(str(tmp_path / "x.obj"))).warnings
    with pytest.raises(ValueError, match="invalid JSON") as error:
        rtcore.Scene.from_bytes(b'{"asset": "' + b"A" * 100000 + b'\xff"}', "y.gltf")
    assert len(str(error.value)) < 1000


def test_tiles_render_alike_on_any_number_of_render_threads(cornell):
    camera = cornell.default_camera
    try:
        images = []
        for threads in (1, 3):
            rtcore.set_render_threads(threads)
            assert rtcore.render_threads() == threads
            images.append(cornell.render_tile(camera, settings(), 2, 3, 44, 31, aux=["depth", "bvh_cost"]))
        for name in ("color", "depth", "bvh_cost", "rays", "samples"):
            np.testing.assert_array_equal(images[0][name], images[1][name])
    finally:
        rtcore.set_render_threads(0)
    assert rtcore.render_threads() == (os.cpu_count() or 1)


def test_tiles_render_concurrently_from_threads(cornell):
    camera, results = cornell.default_camera, {}

    def work(k):
        results[k] = cornell.render_tile(camera, settings(), 0, 12 * k, 48, 12)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    full = cornell.render(camera, settings())
    np.testing.assert_array_equal(np.concatenate([results[k] for k in range(3)]), full)


def test_parse_message_fills_defaults_and_names_bad_fields():
    from rt import job_pb2

    data = rtcore.parse_message("rt.JobRequest", json.dumps(
        {"sceneId": "s1", "camera": {"position": [0, 1, 2], "target": [0, 0, 0]}, "settings": {"width": 64}}))
    request = job_pb2.JobRequest.FromString(data)
    assert request.settings.width == 64 and request.settings.height == 480
    assert request.camera.fov_y == 45
    with pytest.raises(ValueError, match=r"^body\.settings\.max_depth: 65 is above the maximum 64$"):
        rtcore.parse_message("rt.JobRequest", '{"settings": {"maxDepth": 65}}')
    with pytest.raises(ValueError, match="widht"):
        rtcore.parse_message("rt.RenderSettings", '{"widht": 3}')
    with pytest.raises(ValueError, match="unknown message type rt.Nope"):
        rtcore.parse_message("rt.Nope", "{}")


@pytest.mark.parametrize("name", ["cornell.obj", "bunny.glb"])
def test_to_glb_reloads_as_the_same_scene(scenes_dir, name):
    scene = rtcore.Scene.load(str(scenes_dir / name))
    glb = scene.to_glb()
    assert isinstance(glb, bytes)
    assert glb[:4] == b"glTF"
    assert int.from_bytes(glb[4:8], "little") == 2 and int.from_bytes(glb[8:12], "little") == len(glb)
    back = rtcore.Scene.from_bytes(glb, "x.glb")
    assert back.triangle_count == scene.triangle_count
    np.testing.assert_array_equal(scene_info(back).bounds_min, scene_info(scene).bounds_min)
    np.testing.assert_array_equal(scene_info(back).bounds_max, scene_info(scene).bounds_max)
    assert [light.position for light in scene_info(back).lights] == \
        [light.position for light in scene_info(scene).lights]


ALL_AUX = ["depth", "normal", "albedo", "bvh_cost"]


def test_aux_layers_come_with_the_colour(cornell):
    camera = cornell.default_camera
    plain = cornell.render_tile(camera, settings(), 0, 0, 48, 36)
    result = cornell.render_tile(camera, settings(), 0, 0, 48, 36, aux=ALL_AUX)
    assert set(result) == {"color", "depth", "normal", "albedo", "bvh_cost", "rays", "samples"}
    np.testing.assert_array_equal(result["color"], plain)
    assert result["depth"].shape == (36, 48) and result["depth"].dtype == np.float32
    assert result["normal"].shape == result["albedo"].shape == (36, 48, 3)
    assert result["bvh_cost"].shape == (36, 48, 2) and result["bvh_cost"].dtype == np.uint32
    assert result["rays"] >= 48 * 36

    hit = result["depth"] > 0
    assert hit.mean() > 0.5, "the box fills most of the view"
    np.testing.assert_allclose(np.linalg.norm(result["normal"][hit], axis=1), 1.0, atol=1e-5)
    assert (result["albedo"][hit] > 0).any(axis=1).all()
    assert (result["normal"][~hit] == 0).all() and (result["albedo"][~hit] == 0).all()
    assert (result["bvh_cost"][hit] > 0).all()

    # Proto enum values name the same layers; only the ones asked for come back.
    from rt import job_pb2

    by_value = cornell.render_tile(camera, settings(), 0, 0, 48, 36, aux=[job_pb2.DEPTH])
    assert set(by_value) == {"color", "depth", "rays", "samples"}
    np.testing.assert_array_equal(by_value["depth"], result["depth"])
    assert by_value["rays"] == result["rays"]


def test_normals_face_the_camera_but_in_the_mirror(cornell):
    camera = render_pb2.Camera.FromString(cornell.default_camera)
    # At max_depth 0 no ray leaves the mirror: every normal is a primary hit's.
    result = cornell.render_tile(cornell.default_camera, settings(max_depth=0), 0, 0, 48, 36, aux=["normal", "depth"])
    # A ray through each pixel centre, as the pinhole camera makes it.
    position, target = np.array(camera.position), np.array(camera.target)
    forward = (target - position) / np.linalg.norm(target - position)
    right = np.cross(forward, camera.up or [0, 1, 0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    tan_y = np.tan(np.radians(camera.fov_y) / 2)
    ys, xs = np.mgrid[0:36, 0:48] + 0.5
    directions = (forward + (2 * xs / 48 - 1)[..., None] * right * tan_y * 48 / 36
                  + (1 - 2 * ys / 36)[..., None] * up * tan_y)
    hit = result["depth"] > 0
    assert (np.einsum("ijk,ijk->ij", result["normal"], directions)[hit] < 0).all()
    # With reflections, the mirror's pixels hold the normal of what it shows, facing the reflected rays.
    deep = cornell.render_tile(cornell.default_camera, settings(), 0, 0, 48, 36, aux=["normal"])["normal"]
    moved = hit & (np.abs(deep - result["normal"]).max(axis=2) > 1e-3)
    assert 20 < moved.sum() < 0.5 * hit.sum()


def test_bvh_cost_grows_with_max_depth_in_the_mirror(cornell):
    mirror = named_camera(cornell, "mirror")
    costs = [cornell.render_tile(mirror, settings(max_depth=d), 0, 0, 48, 36, aux=["bvh_cost"])
             for d in (0, 1)]
    assert costs[1]["bvh_cost"].astype(np.int64).sum() > costs[0]["bvh_cost"].astype(np.int64).sum()
    assert costs[1]["rays"] > costs[0]["rays"]


def test_bad_aux_names_are_refused(cornell):
    with pytest.raises(ValueError, match="unknown auxiliary output 'speed'"):
        cornell.render_tile(cornell.default_camera, settings(), 0, 0, 4, 4, aux=["speed"])
    with pytest.raises(ValueError, match="unknown auxiliary output 9"):
        cornell.render_tile(cornell.default_camera, settings(), 0, 0, 4, 4, aux=[9])
    with pytest.raises(ValueError, match="list of names"):
        cornell.render_tile(cornell.default_camera, settings(), 0, 0, 4, 4, aux="depth")


def test_preview_tile_pixels_are_the_final_pixels(cornell):
    mirror = named_camera(cornell, "mirror")
    x, y, w, h = 3, 5, 30, 26
    full = cornell.render_tile(mirror, settings(), x, y, w, h, aux=ALL_AUX)
    preview = cornell.render_tile(mirror, settings(), x, y, w, h, aux=ALL_AUX, scale=4)
    assert preview["color"].shape == (7, 8, 3)  # ceil(26 / 4), ceil(30 / 4)
    for key in ("color", *ALL_AUX):
        np.testing.assert_array_equal(preview[key], full[key][::4, ::4], err_msg=key)
    np.testing.assert_array_equal(cornell.render_tile(mirror, settings(), x, y, w, h, scale=4),
                                  full["color"][::4, ::4])
    with pytest.raises(ValueError, match="scale must be at least 1"):
        cornell.render_tile(mirror, settings(), x, y, w, h, scale=0)


@pytest.fixture(scope="module")
def sphere_light(scenes_dir):
    return rtcore.Scene.load(str(scenes_dir / "cornell_sphere_light.obj"))


def test_render_tile_counts_the_samples(sphere_light):
    camera = sphere_light.default_camera
    uniform = sphere_light.render_tile(camera, settings(32, 24, samples_per_pixel=4, light_samples=2),
                                       0, 0, 16, 12, aux=[])
    assert set(uniform) == {"color", "rays", "samples"}
    assert uniform["samples"] == 16 * 12 * 4
    assert uniform["rays"] >= uniform["samples"]
    preview = sphere_light.render_tile(camera, settings(32, 24, samples_per_pixel=4), 0, 0, 16, 12, aux=[], scale=4)
    assert preview["samples"] == 4 * 3 * 4  # only the preview's own pixels

    # Adaptive: at least the minimum (32 at threshold 0.2), in batches of 8, at most samples_per_pixel.
    adaptive = settings(32, 24, samples_per_pixel=128, adaptive_threshold=0.2, light_samples=1)
    total = sphere_light.render_tile(camera, adaptive, 0, 0, 32, 24, aux=[])["samples"]
    assert 32 * 32 * 24 < total < 128 * 32 * 24
    pixel = sphere_light.render_tile(camera, adaptive, 5, 7, 1, 1, aux=[])["samples"]
    assert pixel % 8 == 0 and 32 <= pixel <= 128


def test_a_tile_stops_when_its_stop_source_asks(sphere_light):
    camera = sphere_light.default_camera
    slow = settings(256, 256, samples_per_pixel=256, light_samples=16)  # seconds of both cores
    stop = rtcore.StopSource()
    assert not stop.stop_requested
    threading.Timer(0.05, stop.request_stop).start()
    with pytest.raises(rtcore.RenderStopped):
        sphere_light.render_tile(camera, slow, 0, 0, 256, 256, stop=stop)
    assert stop.stop_requested and issubclass(rtcore.RenderStopped, RuntimeError)
    with pytest.raises(rtcore.RenderStopped):  # a stopped source stops every later tile at once
        sphere_light.render_tile(camera, slow, 0, 0, 256, 256, stop=stop)
    fresh = sphere_light.render_tile(camera, settings(), 0, 0, 8, 8, stop=rtcore.StopSource())
    assert np.array_equal(fresh, sphere_light.render_tile(camera, settings(), 0, 0, 8, 8))
    with pytest.raises(TypeError):
        sphere_light.render_tile(camera, settings(), 0, 0, 8, 8, stop=True)


def test_sampling_settings_have_defaults_and_refuse_bad_values(cornell):
    defaults = render_pb2.RenderSettings.FromString(rtcore.parse_message("rt.RenderSettings", "{}"))
    assert defaults.samples_per_pixel == 1 and defaults.adaptive_threshold == 0
    assert defaults.pixel_filter == render_pb2.GAUSSIAN and defaults.light_sampling == render_pb2.CONE
    given = render_pb2.RenderSettings.FromString(rtcore.parse_message(
        "rt.RenderSettings", '{"pixelFilter": "GRID", "lightSampling": "SPHERE", "samplesPerPixel": 9}'))
    assert (given.pixel_filter, given.light_sampling, given.samples_per_pixel) == (render_pb2.GRID, render_pb2.SPHERE, 9)

    camera = cornell.default_camera
    with pytest.raises(ValueError, match=r"^settings\.samples_per_pixel: 0 is below the minimum 1$"):
        cornell.render_tile(camera, settings(8, 8, samples_per_pixel=0), 0, 0, 1, 1)
    with pytest.raises(ValueError, match=r"^settings\.samples_per_pixel: 70000 is above the maximum 65536$"):
        cornell.render_tile(camera, '{"samplesPerPixel": 70000}', 0, 0, 1, 1)
    with pytest.raises(ValueError, match=r"^settings\.adaptive_threshold: 2 is above the maximum 1$"):
        cornell.render_tile(camera, settings(8, 8, adaptive_threshold=2), 0, 0, 1, 1)
    with pytest.raises(ValueError, match="LANCZOS"):
        cornell.render_tile(camera, '{"pixelFilter": "LANCZOS"}', 0, 0, 1, 1)
    with pytest.raises(ValueError, match=r"settings\.pixel_filter: 7 is not one of GAUSSIAN, BOX, TENT, GRID"):
        cornell.render_tile(camera, settings(8, 8, pixel_filter=7), 0, 0, 1, 1)
    with pytest.raises(ValueError, match=r"settings\.samples_per_pixel: GRID takes a square number"):
        cornell.render_tile(camera, settings(8, 8, pixel_filter=render_pb2.GRID, samples_per_pixel=10), 0, 0, 1, 1)
    with pytest.raises(ValueError, match=r"settings\.adaptive_threshold: adaptive sampling"):
        cornell.render_tile(camera, settings(8, 8, pixel_filter=render_pb2.GRID, samples_per_pixel=16,
                                             adaptive_threshold=0.1), 0, 0, 1, 1)


def test_one_sample_per_pixel_is_the_default_image(cornell):
    camera = cornell.default_camera
    default = cornell.render_tile(camera, settings(), 0, 0, 48, 36)
    for name in ("BOX", "TENT", "GAUSSIAN", "GRID"):
        explicit = cornell.render_tile(camera, json.dumps({"width": 48, "height": 36, "samplesPerPixel": 1,
                                                           "pixelFilter": name}), 0, 0, 48, 36)
        np.testing.assert_array_equal(explicit, default, err_msg=name)
    smooth = cornell.render_tile(camera, settings(samples_per_pixel=16, pixel_filter=render_pb2.BOX), 0, 0, 48, 36)
    assert not np.array_equal(smooth, default), "16 samples per pixel smooth the box's edges"
    np.testing.assert_allclose(smooth.mean(), default.mean(), rtol=0.05)


def test_shadow_rays_name_the_light_they_aim_at(scenes_dir, tmp_path):
    import shutil

    for name in ("cornell.obj", "cornell.mtl"):
        shutil.copy(scenes_dir / name, tmp_path / name)
    point, sphere = [0.0, 1.9, 0.0], [0.3, 1.7, 0.2]
    (tmp_path / "cornell.rt.json").write_text(json.dumps({"lights": [
        {"position": point, "intensity": 1}, {"position": sphere, "intensity": 1, "radius": 0.05}]}))
    scene = rtcore.Scene.load(str(tmp_path / "cornell.obj"))
    path = debug_pb2.DebugPath.FromString(scene.debug_path(scene.default_camera, settings(light_samples=4), 24, 30))
    shadows = [s for s in path.segments if s.kind == debug_pb2.SHADOW]
    assert {s.light for s in shadows} == {0, 1}, "the floor pixel sends shadow rays to both lights"
    for s in shadows:
        aim = np.array(point if s.light == 0 else sphere)
        reach = 1e-4 if s.light == 0 else 0.05 * 1.001
        assert np.linalg.norm(np.array(s.end) - aim) <= reach
    assert sum(s.light == 1 for s in shadows) == 4, "light_samples rays at the spherical light"


def test_encode_srgb8_applies_exposure_and_tone_map():
    rgb = (np.random.default_rng(3).random((20, 30, 3)) * 4).astype(np.float32)
    default = rtcore.encode_srgb8(rgb)
    assert default.shape == (20, 30, 4) and default.dtype == np.uint8 and (default[..., 3] == 255).all()
    for same in (None, "{}", b"", '{"exposure": 0, "toneMap": "CLIP"}'):
        np.testing.assert_array_equal(rtcore.encode_srgb8(rgb, same), default, err_msg=repr(same))
    # A stop more is the image doubled, before the curve.
    for curve in ("CLIP", "REINHARD", "ACES"):
        np.testing.assert_array_equal(rtcore.encode_srgb8(rgb, json.dumps({"exposure": 1, "toneMap": curve})),
                                      rtcore.encode_srgb8(rgb * 2, json.dumps({"toneMap": curve})), err_msg=curve)
    reinhard = rtcore.encode_srgb8(rgb, render_pb2.RenderSettings(tone_map=render_pb2.REINHARD).SerializeToString())
    grey = rtcore.encode_srgb8(np.full((1, 1, 3), 3.0, np.float32), '{"toneMap": "REINHARD"}')
    assert tuple(grey[0, 0, :3]) == (225, 225, 225), "3 / (1 + 3) = 0.75, sRGB code 225"
    assert (reinhard[..., :3] <= default[..., :3]).all() and not np.array_equal(reinhard, default)


def test_apply_bloom_moves_light_without_adding_any():
    rgb = np.full((40, 60, 3), 0.2, np.float32)
    rgb[0, 0] = 30.0  # a corner: its glow must stay inside
    rgb[20, 30] = [50.0, 20.0, 5.0]
    before = rgb.copy()
    out = rtcore.apply_bloom(rgb, '{"bloomStrength": 1, "bloomRadius": 8}')
    assert out.shape == rgb.shape and out.dtype == np.float32
    np.testing.assert_array_equal(rgb, before)  # a new array; the input is left alone
    np.testing.assert_allclose(out.sum(axis=(0, 1), dtype=np.float64), rgb.sum(axis=(0, 1), dtype=np.float64),
                               rtol=1e-5)
    assert out[20, 33, 0] > 0.5 and out[20, 30, 0] < 50.0, "light left the bright pixel for its neighbours"
    assert out[30, 50, 0] == np.float32(0.2), "beyond the glow's reach nothing changes"
    # Strength 0, the default: nothing moves.
    np.testing.assert_array_equal(rtcore.apply_bloom(rgb, None), rgb)
    # Nothing above the threshold: nothing moves either.
    np.testing.assert_array_equal(rtcore.apply_bloom(rgb, '{"bloomStrength": 1, "bloomThreshold": 60}'), rgb)


def test_image_bindings_refuse_bad_shapes_and_settings():
    for bad in (np.zeros((4, 5), np.float32), np.zeros((4, 5, 4), np.float32), np.zeros((2, 4, 5, 3), np.float32)):
        expected = r"\(\): expected an \(height, width, 3\) array, got shape " + re.escape(str(bad.shape))
        with pytest.raises(ValueError, match="apply_bloom" + expected):
            rtcore.apply_bloom(bad, None)
        with pytest.raises(ValueError, match="encode_srgb8" + expected):
            rtcore.encode_srgb8(bad)
    rgb = np.zeros((2, 2, 3), np.float32)
    with pytest.raises(ValueError, match=r"settings\.bloom_strength: 2 is above the maximum 1"):
        rtcore.apply_bloom(rgb, '{"bloomStrength": 2}')
    with pytest.raises(ValueError, match=r"settings\.bloom_radius: 0 is below the minimum 0\.5"):
        rtcore.apply_bloom(rgb, '{"bloomStrength": 1, "bloomRadius": 0}')
    with pytest.raises(ValueError, match="FILMIC"):
        rtcore.encode_srgb8(rgb, '{"toneMap": "FILMIC"}')


def test_bloom_and_display_match_rtrender(rtrender, scenes_dir, tmp_path):
    """The service's way (render, apply_bloom, encode_srgb8) gives rtrender's PNG byte for byte."""
    fields = {"width": 64, "height": 48, "bloomThreshold": 0.4, "bloomRadius": 6, "bloomStrength": 0.7,
              "exposure": 0.5, "toneMap": "ACES"}
    settings_file = tmp_path / "settings.json"
    settings_file.write_text(json.dumps(fields))
    out = tmp_path / "bloom.png"
    result = subprocess.run([str(rtrender), str(scenes_dir / "cornell.obj"), "-o", str(out), "--settings",
                             str(settings_file), "--quiet"], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert "bloom" in result.stdout
    png = np.asarray(Image.open(out).convert("RGB"))

    scene = rtcore.Scene.load(str(scenes_dir / "cornell.obj"))
    linear = scene.render(scene.default_camera, json.dumps(fields))
    bloomed = rtcore.apply_bloom(linear, json.dumps(fields))
    assert not np.array_equal(bloomed, linear), "the threshold is low enough for the lit box to bloom"
    np.testing.assert_array_equal(rtcore.encode_srgb8(bloomed, json.dumps(fields))[..., :3], png)


def test_moving_scenes_and_cameras_blur(scenes_dir):
    """cornell_motion: its short box moves (an rt.NodeMotion in the sidecar) and
    its look_shift camera turns as the 2020 report's did; both blur what they move."""
    scene = rtcore.Scene.load(str(scenes_dir / "cornell_motion.obj"))
    cameras = {c.name: c.camera.SerializeToString() for c in scene_info(scene).cameras}
    shift = render_pb2.Camera.FromString(cameras["look_shift"])
    assert shift.HasField("shutter_close") and shift.shutter_close.target[0] == pytest.approx(0.15)
    still = rtcore.Scene.load(str(scenes_dir / "cornell.obj"))
    camera = cameras["default"]
    moving_box = scene.render_tile(camera, settings(samples_per_pixel=16), 0, 0, 48, 36)
    still_box = still.render_tile(camera, settings(samples_per_pixel=16), 0, 0, 48, 36)
    assert np.abs(moving_box - still_box).max() > 0.1, "the short box moves"

    # The 2020 report's FRAMES: still frames at the centres of the interval's parts, here 2 at times 1/4 and 3/4.
    frames = scene.render_tile(cameras["look_shift"], settings(motion_blur=render_pb2.FRAMES, motion_frames=2),
                               0, 0, 48, 36)
    sampled = scene.render_tile(cameras["look_shift"], settings(samples_per_pixel=64), 0, 0, 48, 36)
    sharp = scene.render_tile(camera, settings(samples_per_pixel=64), 0, 0, 48, 36)
    assert not np.array_equal(frames, sampled)
    assert np.abs(sampled - frames).mean() < 0.5 * np.abs(sharp - frames).mean(), "both blur alike"


def debug_request(camera: str) -> str:
    return json.dumps({"camera": json.loads(camera), "pixel": [0, 0]})


def test_camera_poses_at_shutter_close_are_checked(cornell):
    camera = json.dumps({"position": [0, 0.5, 2], "target": [0, 0.5, 0],
                         "shutterClose": {"position": [0, 0.5, 2], "target": [0, 0.5, 2]}})
    with pytest.raises(ValueError, match=r"^camera\.shutter_close: position and target must differ$"):
        cornell.complete("rt.DebugRayRequest", debug_request(camera))
    with pytest.raises(ValueError, match=r"camera\.shutter_close\.target: is required"):
        cornell.complete("rt.DebugRayRequest", debug_request(
            '{"position": [0, 0, 1], "target": [0, 0, 0], "shutterClose": {"position": [0, 0, 2]}}'))
    defaults = render_pb2.RenderSettings.FromString(rtcore.parse_message("rt.RenderSettings", "{}"))
    assert defaults.motion_blur == render_pb2.TIME_SAMPLED and defaults.motion_frames == 16


def test_complete_fills_the_scene_camera_and_default_settings_once(cornell):
    read = rtcore.parse_message("rt.JobRequest", '{"scene_id": "s", "settings": {"width": 64}}', limits=False)
    assert job_pb2.JobRequest.FromString(read).settings.height == 0, "read only: no defaults yet"
    request = job_pb2.JobRequest.FromString(cornell.complete("rt.JobRequest", read))
    assert request.scene_id == "s"
    assert request.settings.width == 64 and request.settings.height == 480 and request.settings.max_depth > 0
    assert request.camera.SerializeToString() == cornell.default_camera
    given = job_pb2.JobRequest.FromString(cornell.complete(
        "rt.JobRequest", '{"camera": {"position": [0, 1, 2], "target": [0, 0, 0]}, "outputs": ["DEPTH"]}'))
    assert list(given.camera.position) == [0, 1, 2] and given.camera.fov_y == 45
    assert list(given.outputs) == [job_pb2.DEPTH] and given.settings.width == 640


@pytest.mark.parametrize("body, message", [
    ('{"pixel": [0, 0], "settings": {"max_depth": 65}}', r"^settings\.max_depth: 65 is above the maximum 64$"),
    ('{"pixel": [0, 0], "settings": {"samplesPerPixel": 3, "pixelFilter": "GRID"}}', r"^settings\.samples_per_pixel: GRID takes"),
    ('{"pixel": [0, 0], "camera": {"position": [0, 0]}}', r"^camera\.position: needs 3 values, got 2$"),
    ('{"pixel": [1]}', r"^pixel: needs 2 values, got 1$"),
    ('{"pixel": [1, 2], "nope": 1}', r"^body: invalid JSON: .*nope"),
])
def test_complete_names_the_field_as_api_users_write_it(cornell, body, message):
    with pytest.raises(ValueError, match=message):
        cornell.complete("rt.DebugRayRequest", body)


def test_complete_takes_only_render_requests(cornell):
    with pytest.raises(ValueError, match="rt.SceneInfo is not a render request"):
        cornell.complete("rt.SceneInfo", "{}")


def test_a_scene_without_lights_is_lit_by_the_default_rig_unless_turned_off(tmp_path):
    (tmp_path / "tri.obj").write_text("v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n")
    scene = rtcore.Scene.load(str(tmp_path / "tri.obj"))
    info = scene_info(scene)
    assert info.light_rig
    assert [light.kind for light in info.lights] == [scene_pb2.DIRECTIONAL] * 2
    assert all(len(light.direction) == 3 for light in info.lights)
    assert any("default light rig" in w and "NO_RIG" in w for w in info.warnings)
    lit = scene.render_tile(scene.default_camera, settings(16, 16), 0, 0, 16, 16)
    dark = scene.render_tile(scene.default_camera, settings(16, 16, light_rig=render_pb2.NO_RIG), 0, 0, 16, 16)
    assert lit[8, 8, :3].max() > 0 and lit[0, 0, :3].min() > 0, "the triangle lit, the sky behind it"
    assert dark[..., :3].max() == 0, "no rig: black, the background black too"
