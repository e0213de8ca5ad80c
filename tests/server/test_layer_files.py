"""A job's layers on disk: written tile by tile as blocks, read back as images."""

import numpy as np

from app.services import layer_files
from app.services.tile_plan import grid_size, plan_passes


def test_tiles_written_as_blocks_read_back_as_the_image(tmp_path):
    width, height = 300, 170  # edge tiles on both sides
    (full,) = plan_passes(width, height, 2, interactive=False)[-1:]
    folder = layer_files.create(tmp_path, width, height, grid_size(full), ["depth", "bvh_cost"])
    rng = np.random.default_rng(7)
    color = rng.random((height, width, 3), dtype=np.float32)
    depth = rng.random((height, width), dtype=np.float32)
    cost = rng.integers(0, 1000, (height, width, 2), dtype=np.uint32)
    for t in reversed(full):  # any order
        window = (slice(t.y, t.y + t.h), slice(t.x, t.x + t.w))
        layer_files.write_tile(folder, t.x, t.y, {"color": color[window], "depth": depth[window],
                                                  "bvh_cost": cost[window]})
    bloomed = color * 0.5
    layer_files.replace(tmp_path, "color", bloomed)
    layer_files.complete(tmp_path)
    assert layer_files.names(tmp_path) == ["bvh_cost", "color", "depth"]
    np.testing.assert_array_equal(layer_files.load(tmp_path, "color"), bloomed)
    np.testing.assert_array_equal(layer_files.load(tmp_path, "depth")[..., 0], depth)
    np.testing.assert_array_equal(layer_files.load(tmp_path, "bvh_cost"), cost.astype(np.float32))


def test_a_restarted_run_starts_from_empty_files(tmp_path):
    folder = layer_files.create(tmp_path, 32, 32, 16, [])
    layer_files.write_tile(folder, 16, 16, {"color": np.ones((16, 16, 3), np.float32)})
    layer_files.complete(tmp_path)
    folder = layer_files.create(tmp_path, 32, 32, 16, [])
    assert not (tmp_path / layer_files.COMPLETE).exists()
    layer_files.complete(tmp_path)
    assert not layer_files.load(tmp_path, "color").any()
