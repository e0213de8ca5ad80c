// Threads shared by every caller that has work at the same moment: the job
// service's tile tasks. Each caller hands the pool a batch of items and waits;
// the pool's threads take items oldest batch first, so one tile is finished by
// all the cores together and the next tile's items are already queued when it
// is. The cores then never wait for whoever hands out the next tile: with one
// Dask thread per core rendering its own tile, each core sat idle a median
// 2.75 ms between two tiles while the server's event loop dispatched the next
// (7% of a 1024x1024 dragon), and more Dask threads than cores only traded
// that for the cost of time-slicing.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace rt {

// `requested` threads, or every core when it is 0.
unsigned resolve_thread_count(unsigned requested);

class ThreadPool {
  public:
    // `threads` >= 1 threads, started now.
    explicit ThreadPool(unsigned threads);
    // Finishes every batch already handed over, then joins the threads.
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    unsigned size() const { return unsigned(threads_.size()); }

    // Calls body(i) for every i in [0, count) on the pool's threads and
    // returns when all calls have returned. Batches from several callers run
    // first come, first served. When a call throws, the batch's remaining
    // items are skipped and the first exception is rethrown here.
    void parallel_for(size_t count, const std::function<void(size_t)>& body);

  private:
    struct Batch;
    void work();

    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<Batch*> queue_;  // batches with items nobody has taken yet
    bool stopping_ = false;
    std::vector<std::thread> threads_;
};

// The process's render pool (created on first use, all cores by default);
// callers keep the pool they got alive for as long as they use it.
std::shared_ptr<ThreadPool> render_pool();

// Replaces the render pool with one of `threads` threads (0: all cores) unless
// it has that size already. Renders running on the old pool finish on it.
void set_render_threads(unsigned threads);

// Calls body(i) for every i in [0, count) on `threads` threads (0: all cores),
// or on as many as there are items when those are fewer, and returns when all
// calls have returned; an exception as ThreadPool::parallel_for. One thread
// is the caller's own; a request of the render pool's size runs on the render
// pool, sharing the cores with whatever else renders now rather than adding
// threads of its own; any other size on a pool started for the call (the
// caller waits). Not for the render pool's own threads: waiting on the pool
// they belong to, they could all end up waiting.
void parallel_for(unsigned threads, size_t count, const std::function<void(size_t)>& body);

}  // namespace rt
