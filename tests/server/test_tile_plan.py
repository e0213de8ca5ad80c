"""How a job is cut into tiles: passes, coverage, the preview's pixels reused,
and tile sizes that follow the work per pixel."""

import pytest

from rt import job_pb2, render_pb2, scene_pb2

from app.services.tile_plan import (MAX_TILES, PREVIEW_MIN_PIXELS, PREVIEW_MIN_RAYS_PER_THREAD, PREVIEW_SCALE,
                                     TASK_RAYS_PER_THREAD, TILE_RAYS, TILE_SIZES, TILES_PER_THREAD, plan_passes,
                                     rays_per_pixel, schedulable_tiles)


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


@pytest.mark.parametrize("pixel_rays", [1, 2, 17, 64 * 17, 2048 * 2, 1e9])
@pytest.mark.parametrize("width, height, threads", [(1024, 1024, 2), (1920, 1080, 4), (640, 480, 2),
                                                    (4096, 4096, 2), (4096, 4096, 1024), (3840, 2160, 256)])
def test_tiles_keep_every_thread_busy_within_the_ray_budget_and_the_task_limits(width, height, threads, pixel_rays):
    """Enough tiles are two per thread, or as many as the scheduler can hand
    out while the threads render, if fewer; too many are more than MAX_TILES
    (unless the threads need them) or than the scheduler can hand out."""
    full = plan_passes(width, height, threads, interactive=False, pixel_rays=pixel_rays)[-1]
    size = max(t.w for t in full)
    count = lambda s: -(-width // s) * -(-height // s)  # noqa: E731
    schedulable = max(1, width * height * pixel_rays / (threads * TASK_RAYS_PER_THREAD))
    enough = min(TILES_PER_THREAD * threads, schedulable)
    limit = min(max(MAX_TILES, TILES_PER_THREAD * threads), schedulable)
    assert len(full) == count(size)
    assert len(full) >= enough or size == TILE_SIZES[-1]
    largest_enough = max((s for s in TILE_SIZES if count(s) >= enough), default=TILE_SIZES[-1])
    assert len(full) <= limit or size == largest_enough, "more tasks only when threads need them"
    smaller = [s for s in TILE_SIZES if s < size]
    within_budget = size * size * pixel_rays <= TILE_RAYS
    assert within_budget or not smaller or count(smaller[0]) > limit, \
        "over budget only when smaller tiles would be too many"
    # and no larger tile would do as well
    assert all(count(s) < enough or s * s * pixel_rays > TILE_RAYS for s in TILE_SIZES if s > size)


def test_a_large_cluster_gets_no_more_tiles_than_the_scheduler_can_hand_out():
    """A 3840 x 2160 dragon at 16 samples (32 rays a pixel) on 32 workers of 8
    threads: two tiles a thread would be 2040 tiles of 64, and the scheduler,
    at about 1.05 ms a task, would take 2.1 s to hand out what the threads
    render in 0.24 s. It gets 135 tiles of 256 (2.1M rays, over the ray
    budget; 59 ms on a worker of 8 threads). The same image on one such
    worker, at 16 samples or one, keeps its plan."""
    full = plan_passes(3840, 2160, 256, interactive=False, pixel_rays=32)[-1]
    assert {t.w for t in full if t.x + t.w < 3840} == {256} and len(full) == 135
    assert schedulable_tiles(3840, 2160, 256, 32) < 135 < TILES_PER_THREAD * 256
    assert len(plan_passes(3840, 2160, 8, interactive=False, pixel_rays=32)[-1]) == 510  # 128s: the ray budget
    assert len(plan_passes(3840, 2160, 8, interactive=False, pixel_rays=2)[-1]) == 40    # 512s, within budget


def test_the_scheduler_limit_leaves_two_threads_alone_but_for_tiny_images():
    """On 2 threads the limit can bind only below 4 x 2 x TASK_RAYS_PER_THREAD
    (64K) rays: a 90 x 90 image at one sample of one light (16.2K rays) is one
    tile, not 4 of 64; 160 x 120 (38.4K) keeps its 6 tiles of 64."""
    (full,) = plan_passes(90, 90, 2, interactive=False, pixel_rays=2)
    assert len(full) == 1 and (full[0].w, full[0].h) == (90, 90)
    assert len(plan_passes(160, 120, 2, interactive=False, pixel_rays=2)[-1]) == 6


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
