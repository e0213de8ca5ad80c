// The threads every multi-threaded pass of the benchmark runs on, started
// once and kept for the whole run, as a renderer's workers (and Embree's TBB
// threads) are. A thread started for each pass and joined after it cost each
// 2T pass a start-up that the pass's rays were timed with: on this 2-core
// VM, 1M primary rays through smooth_sphere ran at 29.8 Mrays/s on 2 threads
// against 24.0 on 1, as if each pass had lost some 10 ms, and the faster
// side lost the larger share of its time. On the team: 48.0 against 25.4.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <thread>
#include <vector>

#include <immintrin.h>

namespace rt::bench {

class ThreadTeam {
public:
    // The team the benchmark's passes share.
    static ThreadTeam& shared() {
        static ThreadTeam team;
        return team;
    }

    ThreadTeam() = default;
    ThreadTeam(const ThreadTeam&) = delete;
    ThreadTeam& operator=(const ThreadTeam&) = delete;

    ~ThreadTeam() {
        stop_.store(true, std::memory_order_relaxed);
        generation_.fetch_add(1, std::memory_order_release);
        generation_.notify_all();
        for (std::thread& helper : helpers_) helper.join();
    }

    // Runs work() on `threads` threads, the caller one of them, and returns
    // when every one has returned. One caller at a time.
    void run(unsigned threads, const std::function<void()>& work) {
        if (threads <= 1) {
            work();
            return;
        }
        while (helpers_.size() < threads - 1) {
            const unsigned index = unsigned(helpers_.size());
            const uint64_t seen = generation_.load(std::memory_order_relaxed);
            helpers_.emplace_back([this, index, seen] { serve(index, seen); });
        }
        job_ = &work;
        wanted_.store(threads - 1, std::memory_order_relaxed);
        done_.store(0, std::memory_order_relaxed);
        generation_.fetch_add(1, std::memory_order_release);
        generation_.notify_all();
        work();
        while (done_.load(std::memory_order_acquire) < threads - 1) _mm_pause();
    }

private:
    // Helpers spin this long for the next pass before they sleep: a timing
    // window's passes follow each other at once, and a sleeping thread's
    // wake-up is what the team is there to spare them.
    static constexpr std::chrono::milliseconds kSpin{5};

    void serve(unsigned index, uint64_t seen) {
        for (;;) {
            const auto since = std::chrono::steady_clock::now();
            uint64_t now;
            while ((now = generation_.load(std::memory_order_acquire)) == seen) {
                if (std::chrono::steady_clock::now() - since < kSpin) {
                    _mm_pause();
                } else {
                    generation_.wait(seen, std::memory_order_acquire);
                }
            }
            seen = now;
            if (stop_.load(std::memory_order_relaxed)) return;
            // A helper not wanted for this pass may see it late; one that is
            // wanted is waited for before the next pass is set up.
            if (index < wanted_.load(std::memory_order_relaxed)) {
                (*job_)();
                done_.fetch_add(1, std::memory_order_release);
            }
        }
    }

    std::vector<std::thread> helpers_;
    const std::function<void()>* job_ = nullptr;
    std::atomic<uint64_t> generation_{0};
    std::atomic<unsigned> wanted_{0}, done_{0};
    std::atomic<bool> stop_{false};
};

}  // namespace rt::bench
