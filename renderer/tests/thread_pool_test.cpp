#include "util/thread_pool.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <set>
#include <stdexcept>
#include <stop_token>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "integrator/render.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

TEST(ThreadPool, RunsEveryItemOnce) {
    ThreadPool pool(3);
    std::vector<std::atomic<int>> runs(1000);
    pool.parallel_for(runs.size(), [&](size_t i) { ++runs[i]; });
    for (const auto& r : runs) EXPECT_EQ(r.load(), 1);
    pool.parallel_for(0, [](size_t) { FAIL() << "no items, no calls"; });
}

TEST(ThreadPool, CallersShareThePoolAndEachGetsItsOwnItems) {
    ThreadPool pool(2);
    constexpr int kCallers = 6;
    std::vector<std::vector<int>> seen(kCallers, std::vector<int>(200, 0));
    std::vector<std::thread> callers;
    for (int c = 0; c < kCallers; ++c)
        callers.emplace_back([&, c] {
            for (int round = 0; round < 20; ++round) pool.parallel_for(200, [&](size_t i) { ++seen[c][i]; });
        });
    for (auto& t : callers) t.join();
    for (const auto& caller : seen)
        for (int n : caller) EXPECT_EQ(n, 20);
}

TEST(ThreadPool, AnItemsExceptionReachesItsCallerAndThePoolGoesOn) {
    ThreadPool pool(2);
    std::atomic<int> ran{0};
    std::atomic<bool> thrown{false};
    // Items after the throwing one take a millisecond each, so the other thread cannot race
    // through all of them between the throw and the pool's catch, however the threads are scheduled.
    constexpr size_t kItems = 1000;
    EXPECT_THROW(pool.parallel_for(kItems,
                                   [&](size_t i) {
                                       ++ran;
                                       if (i == 3) {
                                           thrown = true;
                                           throw std::runtime_error("item 3");
                                       }
                                       if (i > 3) std::this_thread::sleep_for(std::chrono::milliseconds(1));
                                   }),
                 std::runtime_error);
    EXPECT_LT(ran.load(), int(kItems) / 2) << "the items nobody had taken were skipped";
    EXPECT_TRUE(thrown.load());
    std::atomic<int> after{0};
    pool.parallel_for(50, [&](size_t) { ++after; });
    EXPECT_EQ(after.load(), 50);
}

TEST(ThreadPool, TheRenderPoolIsResizedOnRequest) {
    set_render_threads(3);
    const std::shared_ptr<ThreadPool> held = render_pool();
    EXPECT_EQ(held->size(), 3u);
    set_render_threads(1);
    EXPECT_EQ(render_pool()->size(), 1u);
    // A render still holding the old pool finishes on it.
    std::atomic<int> ran{0};
    held->parallel_for(8, [&](size_t) { ++ran; });
    EXPECT_EQ(ran.load(), 8);
    set_render_threads(0);
    EXPECT_EQ(render_pool()->size(), resolve_thread_count(0));
}

// rt::parallel_for on `threads` threads: every item once, one thread the caller.
TEST(ThreadPool, ParallelForRunsEveryItemOnceOnAsManyThreadsAsAsked) {
    for (unsigned threads : {0u, 1u, 2u, 3u, 5u}) {
        for (size_t count : {0u, 1u, 2u, 7u, 1000u}) {
            std::vector<std::atomic<int>> runs(count);
            std::mutex mutex;
            std::set<std::thread::id> ids;
            parallel_for(threads, count, [&](size_t i) {
                ++runs[i];
                std::lock_guard lock(mutex);
                ids.insert(std::this_thread::get_id());
            });
            for (const auto& r : runs) EXPECT_EQ(r.load(), 1) << threads << " threads, " << count << " items";
            EXPECT_LE(ids.size(), std::min<size_t>(resolve_thread_count(threads), count));
            if (count > 0 && (threads == 1 || count == 1)) {
                EXPECT_EQ(ids, std::set{std::this_thread::get_id()});
            }
        }
    }
    EXPECT_THROW(parallel_for(2, 100, [](size_t i) { if (i == 5) throw std::runtime_error("item 5"); }),
                 std::runtime_error);
    EXPECT_THROW(parallel_for(1, 100, [](size_t i) { if (i == 5) throw std::runtime_error("item 5"); }),
                 std::runtime_error);
}

// Asked for a size other than the render pool's, the items get that many
// threads of their own: three items that each wait for the other two finish.
TEST(ThreadPool, ParallelForOfAnotherSizeGetsThreadsOfItsOwn) {
    set_render_threads(2);
    std::mutex mutex;
    std::condition_variable arrived;
    int waiting = 0;
    std::atomic<int> met{0};
    parallel_for(3, 3, [&](size_t) {
        std::unique_lock lock(mutex);
        ++waiting;
        arrived.notify_all();
        if (arrived.wait_for(lock, std::chrono::seconds(10), [&] { return waiting == 3; })) ++met;
    });
    EXPECT_EQ(met.load(), 3);
    set_render_threads(0);
}

// Asked for the render pool's size, the items queue on the render pool behind
// the tiles it renders already, rather than taking cores beside them.
TEST(ThreadPool, ParallelForOfTheRenderPoolsSizeSharesIt) {
    set_render_threads(2);
    std::mutex mutex;
    std::condition_variable changed;
    bool release = false;
    int busy = 0;
    std::thread tiles([&] {
        render_pool()->parallel_for(2, [&](size_t) {
            std::unique_lock lock(mutex);
            ++busy;
            changed.notify_all();
            changed.wait(lock, [&] { return release; });
        });
    });
    {
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return busy == 2; });  // both pool threads hold a tile
    }
    std::atomic<int> ran{0};
    std::thread caller([&] { parallel_for(2, 4, [&](size_t) { ++ran; }); });
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_EQ(ran.load(), 0) << "the items ran beside the render pool's tiles";
    {
        std::lock_guard lock(mutex);
        release = true;
    }
    changed.notify_all();
    tiles.join();
    caller.join();
    EXPECT_EQ(ran.load(), 4);
    set_render_threads(0);
}

// The floor and sphere of test_scenes.h with its BVH, and renderers of it.
struct LitFloor {
    Scene scene = floor_and_sphere(1.0f);
    Accelerator accel{scene, 1};

    Renderer renderer(uint32_t width, uint32_t height, uint32_t samples) const {
        RenderSettings settings = make_settings(width, height);
        settings.set_samples_per_pixel(samples);
        return Renderer(accel, settings, make_camera({0.0f, 3.0f, 9.0f}, {0.0f, 0.8f, 0.0f}, 40.0f));
    }
};

// A tile rendered in bands on a pool is the tile rendered on one thread: the
// same pixels, layers and counts, for full-resolution tiles and previews.
TEST(ThreadPool, ATileOnThePoolIsTheTileOnOneThread) {
    const LitFloor floor;
    const Renderer renderer = floor.renderer(96, 72, 3);
    ThreadPool pool(3);
    const std::vector<AuxOutput> outputs(std::begin(kAuxOutputs), std::end(kAuxOutputs));
    for (const auto& [tile, scale] : {std::pair{TileRect{0, 0, 96, 72}, 1u}, std::pair{TileRect{8, 5, 70, 53}, 1u},
                                      std::pair{TileRect{0, 0, 96, 72}, 8u}, std::pair{TileRect{3, 2, 90, 67}, 3u}}) {
        const uint32_t w = preview_extent(tile.width, scale), h = preview_extent(tile.height, scale);
        std::vector<float> alone(size_t(w) * h * 3), pooled(alone.size());
        AuxImage alone_aux(w, h, outputs), pooled_aux(w, h, outputs);
        const RenderStats a = renderer.render_tile(tile, alone.data(), alone_aux.layers(), scale);
        const RenderStats b = renderer.render_tile(pool, tile, pooled.data(), pooled_aux.layers(), scale);
        EXPECT_EQ(alone, pooled) << "tile at " << tile.x << ", " << tile.y << " scale " << scale;
        EXPECT_EQ(alone_aux.depth, pooled_aux.depth);
        EXPECT_EQ(alone_aux.normal, pooled_aux.normal);
        EXPECT_EQ(alone_aux.albedo, pooled_aux.albedo);
        EXPECT_EQ(alone_aux.bvh_cost, pooled_aux.bvh_cost);
        EXPECT_EQ(a.samples, b.samples);
        EXPECT_EQ(a.rays.total(), b.rays.total());
    }
    float rgb[3];
    EXPECT_THROW(renderer.render_tile(pool, {90, 0, 7, 1}, rgb), std::invalid_argument);
}

// A cancelled job's tile stops at its next pixel: asked before it starts, it
// traces nothing; asked while it renders, it stops long before it would end.
TEST(ThreadPool, ATileStopsWhenAskedTo) {
    const LitFloor floor;
    const Renderer renderer = floor.renderer(256, 256, 1024);
    ThreadPool pool(2);
    std::vector<float> rgb(256 * 256 * 3, -1.0f);

    std::stop_source before;
    before.request_stop();
    EXPECT_THROW(renderer.render_tile(pool, {0, 0, 256, 256}, rgb.data(), {}, 1, 0, before.get_token()),
                 RenderStopped);
    EXPECT_EQ(std::count(rgb.begin(), rgb.end(), -1.0f), ptrdiff_t(rgb.size())) << "no pixel was traced";

    // The whole tile takes seconds on two cores; the stop comes after 50 ms.
    std::stop_source during;
    std::thread stopper([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        during.request_stop();
    });
    const auto started = std::chrono::steady_clock::now();
    EXPECT_THROW(renderer.render_tile(pool, {0, 0, 256, 256}, rgb.data(), {}, 1, 0, during.get_token()),
                 RenderStopped);
    stopper.join();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    EXPECT_LT(seconds, 2.0);
    const ptrdiff_t untouched = std::count(rgb.begin(), rgb.end(), -1.0f);
    EXPECT_GT(untouched, ptrdiff_t(rgb.size() / 2)) << "the tile went on after the stop";

    // The pool goes on with the next tile.
    std::vector<float> small(8 * 8 * 3);
    EXPECT_EQ(renderer.render_tile(pool, {0, 0, 8, 8}, small.data()).samples, 8u * 8u * 1024u);
}

}  // namespace
}  // namespace rt
