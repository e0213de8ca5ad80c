// The binned SAH builder's threads: fork-join over subtrees and blocks.
#pragma once

#include <algorithm>
#include <atomic>
#include <thread>
#include <utility>

namespace rt::bvh::detail {

// Runs two independent jobs, the first on a helper thread while a spare one
// remains, and loops over blocks on as many spare threads as there are. The
// builder calls it the same way whatever the thread count, so sequential and
// parallel builds share one code path and one result. A thread is spare
// whenever it has nothing to do: a helper hands its thread back as soon as its
// job is done, not when the fork joins (the first split of a mesh is often
// lopsided, the dragon's 1 to 20), and a thread waiting at a join lends its
// own until the join completes.
class ForkJoinExecutor {
  public:
    explicit ForkJoinExecutor(unsigned threads) : spare_threads_(int(std::max(threads, 1u)) - 1) {}

    template <typename First, typename Second>
    void run(First&& first, Second&& second) {
        if (!take_spare_thread()) {
            first();
            second();
            return;
        }
        // Whoever comes first runs `first`: when the helper is slow to start
        // (its core busy elsewhere), this thread does not wait for it.
        std::atomic<bool> claimed{false};
        std::thread helper([this, &first, &claimed] {
            if (!claimed.exchange(true, std::memory_order_acq_rel)) first();
            spare_threads_.fetch_add(1, std::memory_order_relaxed);
        });
        second();
        if (!claimed.exchange(true, std::memory_order_acq_rel)) first();
        spare_threads_.fetch_add(1, std::memory_order_relaxed);
        helper.join();
        spare_threads_.fetch_sub(1, std::memory_order_relaxed);
    }

    // Calls f(i) for every i in [0, count), each exactly once, in any order
    // and on any thread.
    template <typename F>
    void parallel_for(uint32_t count, F&& f) {
        std::atomic<uint32_t> next{0};
        auto work = [&] {
            for (uint32_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < count;) f(i);
        };
        std::thread helpers[kMaxHelpers];
        uint32_t helper_count = 0;
        while (helper_count + 1 < count && helper_count < kMaxHelpers && take_spare_thread()) {
            helpers[helper_count++] = std::thread([this, &work] {
                work();
                spare_threads_.fetch_add(1, std::memory_order_relaxed);
            });
        }
        work();
        for (uint32_t h = 0; h < helper_count; ++h) helpers[h].join();
    }

  private:
    static constexpr uint32_t kMaxHelpers = 63;

    bool take_spare_thread() {
        int spare = spare_threads_.load(std::memory_order_relaxed);
        while (spare > 0)
            if (spare_threads_.compare_exchange_weak(spare, spare - 1, std::memory_order_relaxed))
                return true;
        return false;
    }

    std::atomic<int> spare_threads_;
};

}  // namespace rt::bvh::detail
