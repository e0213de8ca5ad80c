"""How a job is cut into tiles: passes, coverage, and the preview's pixels reused."""

import pytest

from app.services.tile_plan import PREVIEW_MIN_PIXELS, PREVIEW_SCALE, plan_passes


@pytest.mark.parametrize("width, height, threads", [(1024, 1024, 2), (1600, 1200, 8), (300, 240, 2),
                                                    (1001, 777, 3), (4096, 2048, 64)])
def test_tiles_cover_the_image_once_and_reuse_their_previews_pixels(width, height, threads):
    passes = plan_passes(width, height, threads, interactive=False)
    *previews, full = passes
    assert len(previews) == 1, "a large image gets one preview pass"
    covered = [[0] * width for _ in range(height)]
    for tile in full:
        p = tile.preview
        assert p in previews[0], "a tile names a tile of the preview pass"
        assert p.x <= tile.x and tile.x + tile.w <= p.x + p.w and p.y <= tile.y and tile.y + tile.h <= p.y + p.h
        assert (tile.x - p.x) % p.scale == 0 and (tile.y - p.y) % p.scale == 0, "the tile starts on the preview's grid"
        for y in range(tile.y, tile.y + tile.h):
            for x in range(tile.x, tile.x + tile.w):
                covered[y][x] += 1
    assert all(c == 1 for row in covered for c in row)
    # Each pixel is traced once: by the preview on its grid, by its tile elsewhere.
    assert sum(t.pixels for p in passes for t in p) == width * height
    assert sum(t.pixels for t in previews[0]) == -(-width // PREVIEW_SCALE) * -(-height // PREVIEW_SCALE)


def test_small_images_have_no_preview_and_trace_every_pixel_in_their_tiles():
    (full,) = plan_passes(200, 150, 2, interactive=False)
    assert 200 * 150 < PREVIEW_MIN_PIXELS
    assert all(t.preview is None for t in full)
    assert sum(t.pixels for t in full) == 200 * 150


def test_an_interactive_job_outranks_a_batch_job_and_previews_outrank_full_tiles():
    batch = plan_passes(1024, 768, 2, interactive=False)
    interactive = plan_passes(1024, 768, 2, interactive=True)
    assert min(t.priority for p in interactive for t in p) > max(t.priority for p in batch for t in p)
    assert min(t.priority for t in batch[0]) > max(t.priority for t in batch[1])
