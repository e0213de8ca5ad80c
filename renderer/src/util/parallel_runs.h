// Splits a loop over [0, count) into contiguous runs, one per thread, on
// threads started for the call: for the passes of an accelerator's build
// that touch every primitive once (boxes, leaf blocks), which are too short
// to queue on the render pool behind tiles, and may be called from anywhere.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace rt {

// Calls run(begin, end) on disjoint runs covering [0, count), on up to
// `threads` threads (0: all cores), the caller's the first, and returns when
// all have returned. Runs are at least min_run long, so a short loop stays
// on the caller's thread and starts none.
template <typename Run>
void parallel_runs(unsigned threads, size_t count, size_t min_run, Run&& run) {
    const size_t wanted = threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
    const size_t runs = std::max<size_t>(1, std::min(wanted, count / std::max<size_t>(min_run, 1)));
    if (runs == 1) {
        run(size_t(0), count);
        return;
    }
    const size_t length = (count + runs - 1) / runs;
    std::vector<std::thread> helpers;
    helpers.reserve(runs - 1);
    for (size_t r = 1; r < runs; ++r)
        helpers.emplace_back([&run, r, length, count] { run(r * length, std::min(count, (r + 1) * length)); });
    run(size_t(0), length);
    for (std::thread& helper : helpers) helper.join();
}

}  // namespace rt
