"""How a job is cut into tiles: passes, coverage, the preview's pixels reused,
and tile sizes that follow the work per pixel."""

import numpy as np
import pytest

from rt import job_pb2, render_pb2, scene_pb2

from app.services.tile_plan import (MAX_TILES, PREVIEW_MIN_PIXELS, PREVIEW_MIN_RAYS_PER_THREAD, PREVIEW_SCALE,
                                     TASK_RAYS_PER_THREAD, TILE_RAYS, TILE_SIZES, TILES_PER_THREAD, grid_size,
                                     plan_passes, rays_per_pixel, schedulable_tiles)


@pytest.mark.parametrize("width, height, threads", [(1024, 1024, 2), (1600, 1200, 8), (300, 240, 2),
                                                    (1001, 777, 3), (4096, 2048, 64)])
def test_tiles_cover_the_image_once_and_reuse_their_previews_pixels(width, height, threads):
    passes = plan_passes(width, height, threads, interactive=True)
    *previews, full = passes
    assert len(previews) == 1, "a large image someone waits for gets one preview pass"
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
    (full,) = plan_passes(200, 150, 2, interactive=True)
    assert 200 * 150 < PREVIEW_MIN_PIXELS
    assert all(t.preview is None for t in full)
    assert sum(t.pixels for t in full) == 200 * 150


@pytest.mark.parametrize("threads", [2, 64])
def test_a_batch_job_gets_a_preview_only_when_it_takes_long(threads):
    """A preview's pixels cost about twice a full tile's and it is a task
    more: a batch job nobody waits for skips it unless it runs long."""
    pixels = 1024 * 1024
    short = PREVIEW_MIN_RAYS_PER_THREAD * threads / pixels  # rays per pixel at the threshold
    assert len(plan_passes(1024, 1024, threads, interactive=False, pixel_rays=short)) == 1
    assert len(plan_passes(1024, 1024, threads, interactive=False, pixel_rays=short * 1.01)) == 2
    assert len(plan_passes(1024, 1024, threads, interactive=True, pixel_rays=1)) == 2
    # The service benchmark's 1024 x 1024 dragon at one sample (two lights), on 2 threads, has none.
    assert len(plan_passes(1024, 1024, 2, interactive=False, pixel_rays=3)) == 1


def test_an_interactive_job_outranks_a_batch_job_and_previews_outrank_full_tiles():
    batch = plan_passes(1024, 768, 2, interactive=False, pixel_rays=64)
    assert len(batch) == 2, "a long batch job has a preview"
    interactive = plan_passes(1024, 768, 2, interactive=True)
    assert min(t.priority for p in interactive for t in p) > max(t.priority for p in batch for t in p)
    assert min(t.priority for t in batch[0]) > max(t.priority for t in batch[1])


def limits(width: int, height: int, threads: int, pixel_rays: float) -> tuple[float, float, bool]:
    """Enough tiles, too many, and whether the scheduler sets that limit, worked out from the constants."""
    schedulable = max(1, width * height * pixel_rays / (threads * TASK_RAYS_PER_THREAD))
    enough = min(TILES_PER_THREAD * threads, schedulable)
    limit = min(max(MAX_TILES, TILES_PER_THREAD * threads), schedulable)
    return enough, limit, schedulable < max(MAX_TILES, TILES_PER_THREAD * threads)


def cut_tiles(full: list, width: int, height: int, edge: int) -> list[tuple[int, int, int, int]]:
    """The tiles of the grid of `edge` that `full` has cut in four, asserting
    that it is that grid with some tiles cut so."""
    tiles = {(t.x, t.y, t.w, t.h) for t in full}
    assert len(tiles) == len(full)
    cut = []
    for y in range(0, height, edge):
        for x in range(0, width, edge):
            w, h = min(edge, width - x), min(edge, height - y)
            if (x, y, w, h) in tiles:
                tiles.remove((x, y, w, h))
                continue
            half = edge // 2
            quarters = {(qx, qy, min(half, x + w - qx), min(half, y + h - qy))
                        for qy in range(y, y + h, half) for qx in range(x, x + w, half)}
            assert quarters <= tiles, f"the tile at {x}, {y} is neither whole nor cut in four"
            tiles -= quarters
            cut.append((x, y, w, h))
    assert not tiles, "every tile is one of the grid's or a quarter of one"
    return cut


@pytest.mark.parametrize("pixel_rays", [1, 2, 17, 64 * 17, 2048 * 2, 1e9])
@pytest.mark.parametrize("width, height, threads", [(1024, 1024, 2), (1920, 1080, 4), (640, 480, 2),
                                                    (4096, 4096, 2), (4096, 4096, 1024), (3840, 2160, 256),
                                                    (3840, 2160, 512)])
def test_tiles_keep_every_thread_busy_within_the_ray_budget_and_the_task_limits(width, height, threads, pixel_rays):
    """Enough tiles are two per thread, or as many as the scheduler can hand
    out while the threads render, if fewer; too many are more than MAX_TILES
    (unless the threads need them) or than the scheduler can hand out. Where
    the scheduler's limit falls between two tile sizes, the larger is taken
    and its middle tiles cut in four up to the limit."""
    full = plan_passes(width, height, threads, interactive=False, pixel_rays=pixel_rays)[-1]
    grid = max(max(t.w, t.h) for t in full)  # the uncut tiles' edge
    count = lambda s: -(-width // s) * -(-height // s)  # noqa: E731
    enough, limit, scheduler_limited = limits(width, height, threads, pixel_rays)
    cut = cut_tiles(full, width, height, grid)
    finer_too_many = grid == TILE_SIZES[-1] or count(grid // 2) > limit
    within_budget = grid * grid * pixel_rays <= TILE_RAYS
    if scheduler_limited and finer_too_many:
        assert len(full) <= limit or count(grid) > limit, "no more than the scheduler can hand out"
        if (count(grid) < enough or not within_budget) and grid > TILE_SIZES[-1]:
            assert len(full) > limit - 3 or count(grid) > limit - 3, "as many cut as the scheduler has room for"
        centre = lambda r: ((r[0] + r[2] / 2 - width / 2) ** 2 + (r[1] + r[3] / 2 - height / 2) ** 2)  # noqa: E731
        kept = [(t.x, t.y, t.w, t.h) for t in full if max(t.w, t.h) == grid]
        assert all(centre(c) <= centre(k) for c in cut for k in kept), "the middle tiles are cut"
    else:
        assert not cut, "cut only where the scheduler's limit stopped the grid"
        assert len(full) >= enough or grid == TILE_SIZES[-1]
        largest_enough = max((s for s in TILE_SIZES if count(s) >= enough), default=TILE_SIZES[-1])
        assert len(full) <= limit or grid == largest_enough, "more tasks only when threads need them"
    assert within_budget or grid == TILE_SIZES[-1] or finer_too_many, \
        "over budget only when smaller tiles would be too many"
    # and no larger tile would do as well
    assert all(count(s) < enough or s * s * pixel_rays > TILE_RAYS for s in TILE_SIZES if s > grid)


def test_a_large_cluster_gets_as_many_tiles_as_the_scheduler_can_hand_out_the_middle_ones_cut_and_last():
    """A 3840 x 2160 dragon at 16 samples (32 rays a pixel) on 32 workers of 8
    threads: the scheduler can hand out 202 tasks while the threads render
    (two tiles a thread would be 2040 tiles of 64), between 135 tiles of 256
    and 510 of 128. It gets the 256s with the 22 middle ones cut in four:
    113 tiles of 256 (15 cut short by the image's edge), then 88 of 128, which
    run last, centre-out. The same image on one such worker, at 16 samples or
    one, keeps its plan."""
    assert 135 < schedulable_tiles(3840, 2160, 256, 32) < 510
    full = plan_passes(3840, 2160, 256, interactive=False, pixel_rays=32)[-1]
    large = [t for t in full if t.w == 256]
    quarters = [t for t in full if t.w == 128]
    assert len(full) == 201 and len(large) == 113 and len(quarters) == 88 and full[113:] == quarters
    assert max(t.priority for t in quarters) < min(t.priority for t in large), "the quarters run last"
    centre = lambda t: ((t.x + t.w / 2 - 1920) ** 2 + (t.y + t.h / 2 - 1080) ** 2) ** 0.5  # noqa: E731
    assert max(map(centre, quarters)) < min(map(centre, large)) + 256, "they are the middle's"
    assert [centre(t) for t in quarters] == sorted(centre(t) for t in quarters)
    assert grid_size(full) == 128
    assert len(plan_passes(3840, 2160, 8, interactive=False, pixel_rays=32)[-1]) == 510  # 128s: the ray budget
    assert len(plan_passes(3840, 2160, 8, interactive=False, pixel_rays=2)[-1]) == 40    # 512s, within budget


def test_cut_tiles_cover_the_image_once_on_the_grid_of_the_layer_files():
    """Tiles of two sizes: each pixel in one tile, each tile in one preview
    tile, starting on grid_size's grid and covering whole blocks of it (or
    ending at the image's edge)."""
    width, height = 3840, 2160
    *previews, full = plan_passes(width, height, 256, interactive=True, pixel_rays=32)
    grid = grid_size(full)
    assert {max(t.w, t.h) for t in full} == {256, 128} and grid == 128
    covered = np.zeros((height, width), np.uint8)
    for t in full:
        covered[t.y:t.y + t.h, t.x:t.x + t.w] += 1
        assert t.x % grid == 0 and t.y % grid == 0
        assert (t.w % grid == 0 or t.x + t.w == width) and (t.h % grid == 0 or t.y + t.h == height)
        p = t.preview
        assert p in previews[0] and p.x <= t.x and t.x + t.w <= p.x + p.w and p.y <= t.y and t.y + t.h <= p.y + p.h
    assert (covered == 1).all()
    assert sum(t.pixels for p in (*previews, full) for t in p) == width * height


def test_grid_size_is_the_largest_tiles_edge_or_the_cut_tiles():
    assert grid_size(plan_passes(1024, 1024, 2, False, 2)[-1]) == 512
    assert grid_size(plan_passes(90, 90, 2, False, 2)[-1]) == 90
    assert grid_size(plan_passes(800, 600, 8, False, 1)[-1]) == 256  # 512s, the middle ones cut


def test_the_scheduler_limit_leaves_two_threads_alone_but_for_tiny_images():
    """On 2 threads the limit can bind only below 4 x 2 x TASK_RAYS_PER_THREAD
    (40K) rays: a 160 x 120 image at one sample of one light (38.4K rays) is
    2 tiles (128 and 32 wide), not 6 of 64, a 90 x 90 one tile; 200 x 150
    (60K) keeps its 4 tiles of 128, 640 x 480 its 6 of 256."""
    assert 4 * 2 * TASK_RAYS_PER_THREAD == 40 * 1024
    assert [(t.w, t.h) for t in plan_passes(160, 120, 2, interactive=False, pixel_rays=2)[-1]] == \
        [(128, 120), (32, 120)]
    (full,) = plan_passes(90, 90, 2, interactive=False, pixel_rays=2)
    assert len(full) == 1 and (full[0].w, full[0].h) == (90, 90)
    assert len(plan_passes(200, 150, 2, interactive=False, pixel_rays=2)[-1]) == 4
    small = plan_passes(640, 480, 2, interactive=True, pixel_rays=2)[-1]
    assert len(small) == 6 and grid_size(small) == 256


def test_a_cheap_image_gets_few_large_tiles_and_an_expensive_one_small_tiles():
    cheap = plan_passes(1024, 1024, 2, interactive=False, pixel_rays=2)[-1]
    assert {(t.w, t.h) for t in cheap} == {(512, 512)} and len(cheap) == 4
    costly = plan_passes(1024, 1024, 2, interactive=False, pixel_rays=64 * 17)[-1]
    assert max(t.w for t in costly) <= 32
    # 2048 samples would want 4096 tiles of 16: the task limit makes them 1024 of 32.
    limited = plan_passes(1024, 1024, 2, interactive=False, pixel_rays=2048 * 2)[-1]
    assert {(t.w, t.h) for t in limited} == {(32, 32)} and len(limited) == MAX_TILES


def test_rays_per_pixel_counts_camera_samples_frames_and_shadow_rays():
    point = job_pb2.SceneInfo().lights.add(position=[0, 1, 0])
    sphere = job_pb2.SceneInfo().lights.add(position=[0, 1, 0], radius=0.1)
    settings = render_pb2.RenderSettings(samples_per_pixel=4, light_samples=16)
    assert rays_per_pixel(settings, []) == 4
    assert rays_per_pixel(settings, [point]) == 4 * 2
    assert rays_per_pixel(settings, [point, sphere]) == 4 * (1 + 1 + 16)
    sun = job_pb2.SceneInfo().lights.add(kind=scene_pb2.DIRECTIONAL, direction=[0, -1, 0])
    soft_sun = job_pb2.SceneInfo().lights.add(kind=scene_pb2.DIRECTIONAL, direction=[0, -1, 0], angular_diameter=0.5)
    assert rays_per_pixel(settings, [sun, soft_sun]) == 4 * (1 + 1 + 16)
    settings.motion_blur = render_pb2.FRAMES
    settings.motion_frames = 8
    assert rays_per_pixel(settings, [sphere]) == 4 * 8 * 17
