// Clocks, the parallel loop every query runs in, and the two timers every
// figure of the benchmark comes from: rays per second of a repeated pass, and
// the spread of repeated builds.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <ctime>
#include <memory>
#include <vector>

#include "util/thread_pool.h"

namespace rt::bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Seconds on the calling thread's CPU clock: what one-thread figures are
// timed with, so that whatever else runs on the machine does not skew them.
inline double thread_cpu_seconds() {
    timespec now;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return double(now.tv_sec) + 1e-9 * double(now.tv_nsec);
}

// The threads every multi-threaded pass runs on, started once and kept for
// the whole run, as a renderer's workers (and Embree's TBB threads) are. A
// thread started for each pass and joined after it cost each 2T pass a
// start-up its rays were timed with: on this 2-core VM, 1M primary rays
// through smooth_sphere ran at 29.8 Mrays/s on 2 threads against 24.0 on 1,
// and the faster side lost the larger share of its time.
inline ThreadPool& bench_pool(unsigned threads) {
    static std::unique_ptr<ThreadPool> pool;
    if (!pool || pool->size() != threads) pool = std::make_unique<ThreadPool>(threads);
    return *pool;
}

// Calls f(i) for i in [0, count) on `threads` threads of bench_pool (one
// thread: the caller's own, whose CPU clock times it), in chunks handed out
// in order, so neighbouring rays stay on one thread as a renderer's tiles do.
template <typename F>
void parallel_for(size_t count, unsigned threads, F&& f, size_t chunk = 1024) {
    std::atomic<size_t> next{0};
    const auto work = [&] {
        for (size_t begin; (begin = next.fetch_add(chunk)) < count;)
            for (size_t i = begin; i < std::min(count, begin + chunk); ++i) f(i);
    };
    if (threads <= 1) {
        work();
        return;
    }
    bench_pool(threads).parallel_for(threads, [&](size_t) { work(); });
}

// Rays per second of `pass`, which traces `rays` rays, repeated for at least
// seconds; on the thread's CPU clock when the pass runs on this thread only.
template <typename Pass>
double rays_per_second(size_t rays, double seconds, bool on_this_thread, Pass&& pass) {
    auto now = [&] {
        return on_this_thread ? thread_cpu_seconds()
                              : std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
    };
    size_t passes = 0;
    const double start = now();
    do {
        pass();
        ++passes;
    } while (now() - start < seconds);
    return double(rays * passes) / (now() - start);
}

inline double process_cpu_seconds() {
    timespec now;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return double(now.tv_sec) + 1e-9 * double(now.tv_nsec);
}

// Windows each side's time is split into, in pairs that alternate which
// side goes first (A B, B A, A B, ...). With three windows taken A B A B A B,
// a slow spell of this shared machine that spanned a side's three windows
// could spare the other side's last one, and a side then lost a whole 2T
// figure (make bench: our 2T at our 1T speed on the teapot's shadow packets,
// 120 against 145 Mrays/s, where every A/B run before and after scaled
// 1.5-1.6x). Taken A B, B A, each side leads half the pairs and neither
// always has the other's windows on both sides of its own, so a spell weighs
// on both sides alike; and shorter windows leave it fewer to spoil.
inline constexpr int kTimingWindows = 6;

struct PairTiming {
    double a = 0.0, b = 0.0;  // rays per second
    // CPU seconds the process got per wall second and thread: 1 when each
    // thread had a core of its own, less when other work on the machine took
    // some (which slows both sides, so their ratio still holds).
    double cpu_share = 1.0;
};

// Rays per second of two passes over the same `rays` on `threads` threads, in
// kTimingWindows windows of min_seconds / kTimingWindows each, taking turns,
// and the best window of each: other work on this shared machine only ever
// slows a window down, and taking turns lets a slow spell hit both sides alike.
template <typename PassA, typename PassB>
PairTiming best_rays_per_second(size_t rays, double min_seconds, unsigned threads, PassA&& a, PassB&& b) {
    PairTiming timing;
    const double window = min_seconds / kTimingWindows;
    const auto wall_start = Clock::now();
    const double cpu_start = process_cpu_seconds();
    const auto time_a = [&] { timing.a = std::max(timing.a, rays_per_second(rays, window, threads == 1, a)); };
    const auto time_b = [&] { timing.b = std::max(timing.b, rays_per_second(rays, window, threads == 1, b)); };
    for (int w = 0; w < kTimingWindows; ++w) {
        if (w % 2 == 0) {
            time_a(), time_b();
        } else {
            time_b(), time_a();
        }
    }
    timing.cpu_share = (process_cpu_seconds() - cpu_start) / (seconds_since(wall_start) * threads);
    return timing;
}

// Median and range of repeated measurements: the median is the figure, the
// range says how far this noisy machine let it wander.
struct Spread {
    double median = 0.0, min = 0.0, max = 0.0;
    int runs = 0;
};

inline Spread spread_of(std::vector<double> samples) {
    Spread s;
    if (samples.empty()) return s;
    std::sort(samples.begin(), samples.end());
    const size_t n = samples.size();
    s.median = n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
    s.min = samples.front();
    s.max = samples.back();
    s.runs = int(n);
    return s;
}

// Wall-clock milliseconds of `build()`, `runs` times; what it returns (the
// built tree) is freed after the clock stops. Builds are timed on the wall
// clock even on one thread: a build may hand its work to threads it owns
// (TBB's, our pool's), whose CPU time the caller's clock would miss.
template <typename Build>
Spread build_ms(int runs, Build&& build) {
    std::vector<double> ms;
    for (int r = 0; r < runs; ++r) {
        const auto start = Clock::now();
        const auto built = build();
        ms.push_back(1000.0 * seconds_since(start));
    }
    return spread_of(std::move(ms));
}

}  // namespace rt::bench
