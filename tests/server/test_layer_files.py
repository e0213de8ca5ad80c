"""A job's layers on disk: written tile by tile as blocks, read back as images."""

import errno
import os

import numpy as np
import pytest

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


def test_tiles_of_two_sizes_are_written_as_the_blocks_they_cover(tmp_path):
    """Where the plan cut the middle tiles in four (800 x 600 on 8 threads:
    three of its four tiles of 512 cut to 256, edge tiles of both), the blocks
    are the quarters' and a larger tile is written as each of the blocks it
    covers."""
    width, height = 800, 600
    full = plan_passes(width, height, 8, interactive=False)[-1]
    assert grid_size(full) == 256 and any(t.w > 256 for t in full)
    folder = layer_files.create(tmp_path, width, height, grid_size(full), ["depth"])
    rng = np.random.default_rng(11)
    color = rng.random((height, width, 3), dtype=np.float32)
    depth = rng.random((height, width), dtype=np.float32)
    for t in full:
        window = (slice(t.y, t.y + t.h), slice(t.x, t.x + t.w))
        layer_files.write_tile(folder, t.x, t.y, {"color": color[window], "depth": depth[window]})
    layer_files.complete(tmp_path)
    np.testing.assert_array_equal(layer_files.load(tmp_path, "color"), color)
    np.testing.assert_array_equal(layer_files.load(tmp_path, "depth")[..., 0], depth)


@pytest.mark.parametrize("width, height, tile", [(48, 36, 48), (100, 20, 64), (40, 100, 64)])
def test_a_layer_loads_as_a_writable_array_however_few_its_blocks(tmp_path, width, height, tile):
    """A job of one tile (or one column of them) reads back as an array of
    its own, as one of many does, not as a view of the read-only file."""
    folder = layer_files.create(tmp_path, width, height, tile, [])
    color = np.random.default_rng(3).random((height, width, 3), dtype=np.float32)
    for y in range(0, height, tile):
        for x in range(0, width, tile):
            layer_files.write_tile(folder, x, y, {"color": color[y:y + tile, x:x + tile]})
    layer_files.complete(tmp_path)
    image = layer_files.load(tmp_path, "color")
    assert image.flags.writeable
    np.testing.assert_array_equal(image, color)


def test_a_restarted_run_starts_from_empty_files(tmp_path):
    folder = layer_files.create(tmp_path, 32, 32, 16, [])
    layer_files.write_tile(folder, 16, 16, {"color": np.ones((16, 16, 3), np.float32)})
    layer_files.complete(tmp_path)
    folder = layer_files.create(tmp_path, 32, 32, 16, [])
    assert not (tmp_path / layer_files.COMPLETE).exists()
    layer_files.complete(tmp_path)
    assert not layer_files.load(tmp_path, "color").any()


def _record_opens(monkeypatch, refuse_direct=False):
    flags = []
    real_open = layer_files.os.open

    def recording_open(path, mode, *args):
        flags.append(mode)
        if refuse_direct and mode & os.O_DIRECT:
            raise OSError(errno.EINVAL, "Invalid argument", str(path))
        return real_open(path, mode, *args)

    monkeypatch.setattr(layer_files.os, "open", recording_open)
    return flags


def _write_in_tiles(folder, tile, color):
    """Writes `color`, and its red as a depth layer, tile by tile."""
    height, width = color.shape[:2]
    for y in range(0, height, tile):
        for x in range(0, width, tile):
            layer_files.write_tile(folder, x, y, {"color": color[y:y + tile, x:x + tile],
                                                  "depth": color[y:y + tile, x:x + tile, 0]})


def _assert_read_back(job_folder, color):
    layer_files.complete(job_folder)
    np.testing.assert_array_equal(layer_files.load(job_folder, "color"), color)
    np.testing.assert_array_equal(layer_files.load(job_folder, "depth")[..., 0], color[..., 0])


@pytest.mark.parametrize("refuse_direct", [False, True], ids=["direct", "filesystem-without-O_DIRECT"])
def test_tiles_of_32_pixels_or_more_go_past_the_page_cache(tmp_path, monkeypatch, refuse_direct):
    width, height, tile = 100, 70, 32  # edge tiles of 4 and 6 pixels
    folder = layer_files.create(tmp_path, width, height, tile, ["depth"])
    with open(folder / "color.npy", "rb") as f:
        np.lib.format.read_magic(f)
        np.lib.format.read_array_header_1_0(f)
        assert f.tell() == layer_files.DIRECT_ALIGN  # blocks start aligned
    flags = _record_opens(monkeypatch, refuse_direct)
    color = np.random.default_rng(3).random((height, width, 3), dtype=np.float32)
    _write_in_tiles(folder, tile, color)
    assert sum(1 for f in flags if f & os.O_DIRECT) == 2 * 4 * 3  # every block of both layers tried it
    _assert_read_back(tmp_path, color)


def test_smaller_tiles_go_through_the_cache(tmp_path, monkeypatch):
    """A 16-pixel tile's depth block (1 KB) cannot meet O_DIRECT's alignment."""
    width, height, tile = 40, 20, 16
    folder = layer_files.create(tmp_path, width, height, tile, ["depth"])
    flags = _record_opens(monkeypatch)
    color = np.random.default_rng(5).random((height, width, 3), dtype=np.float32)
    _write_in_tiles(folder, tile, color)
    assert not any(f & os.O_DIRECT for f in flags)
    _assert_read_back(tmp_path, color)


def test_layer_files_are_read_without_python_s_parser(tmp_path, monkeypatch):
    """numpy reads a .npy header with ast.literal_eval, which CPython 3.11
    cannot run in two threads at once (gh-106905: a render thread's tile failed
    with "AST constructor recursion depth mismatch"); tiles are written and
    layers read without it."""
    def refuse(*args, **kwargs):
        raise AssertionError("ast.literal_eval called")

    monkeypatch.setattr("ast.literal_eval", refuse)
    width, height, tile = 70, 40, 32
    folder = layer_files.create(tmp_path, width, height, tile, ["depth"])
    color = np.random.default_rng(11).random((height, width, 3), dtype=np.float32)
    _write_in_tiles(folder, tile, color)
    layer_files.replace(tmp_path, "depth", color[..., :1] * 2)
    layer_files.complete(tmp_path)
    np.testing.assert_array_equal(layer_files.load(tmp_path, "color"), color)
    np.testing.assert_array_equal(layer_files.load(tmp_path, "depth")[..., 0], color[..., 0] * 2)


def test_a_file_that_is_not_a_layer_file_is_named(tmp_path):
    folder = layer_files.create(tmp_path, 16, 16, 16, [])
    (folder / "color.npy").write_bytes(b"\x93NUMPY\x01\x00\x10\x00{'descr': '<i8'}")
    with pytest.raises(ValueError, match="color.npy: not a layer file"):
        layer_files.write_tile(folder, 0, 0, {"color": np.zeros((16, 16, 3), np.float32)})
