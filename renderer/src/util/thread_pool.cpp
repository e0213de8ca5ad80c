#include "util/thread_pool.h"

#include <algorithm>
#include <exception>
#include <utility>

namespace rt {

unsigned resolve_thread_count(unsigned requested) {
    return requested != 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
}

struct ThreadPool::Batch {
    size_t count = 0;
    const std::function<void(size_t)>* body = nullptr;
    size_t next = 0;       // the next item to hand out
    size_t running = 0;    // items handed out and not yet returned
    bool failed = false;   // an item threw: hand out no more
    std::exception_ptr error;
    std::condition_variable done;
};

ThreadPool::ThreadPool(unsigned threads) {
    threads_.reserve(threads);
    for (unsigned t = 0; t < std::max(threads, 1u); ++t) threads_.emplace_back([this] { work(); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    for (auto& thread : threads_) thread.join();
}

void ThreadPool::parallel_for(size_t count, const std::function<void(size_t)>& body) {
    if (count == 0) return;
    Batch batch;
    batch.count = count;
    batch.body = &body;
    std::unique_lock lock(mutex_);
    queue_.push_back(&batch);
    wake_.notify_all();
    batch.done.wait(lock, [&] { return batch.next == batch.count && batch.running == 0; });
    if (batch.error) std::rethrow_exception(batch.error);
}

void ThreadPool::work() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
        if (queue_.empty()) return;  // stopping, and every batch handed out
        Batch& batch = *queue_.front();
        const size_t item = batch.next++;
        if (batch.next == batch.count) queue_.pop_front();
        ++batch.running;
        lock.unlock();
        try {
            (*batch.body)(item);
        } catch (...) {
            lock.lock();
            if (!batch.error) batch.error = std::current_exception();
            if (!batch.failed && batch.next < batch.count) {
                batch.failed = true;
                batch.next = batch.count;  // skip what nobody has taken
                std::erase(queue_, &batch);
            }
            lock.unlock();
        }
        lock.lock();
        if (--batch.running == 0 && batch.next == batch.count) batch.done.notify_one();
    }
}

namespace {

std::mutex pool_mutex;
std::shared_ptr<ThreadPool> shared_pool;

}  // namespace

std::shared_ptr<ThreadPool> render_pool() {
    std::lock_guard lock(pool_mutex);
    if (!shared_pool) shared_pool = std::make_shared<ThreadPool>(resolve_thread_count(0));
    return shared_pool;
}

void set_render_threads(unsigned threads) {
    const unsigned size = resolve_thread_count(threads);
    std::shared_ptr<ThreadPool> old;
    {
        std::lock_guard lock(pool_mutex);
        if (shared_pool && shared_pool->size() == size) return;
        old = std::exchange(shared_pool, std::make_shared<ThreadPool>(size));
    }
    // `old` is joined here, outside the lock, unless a render still holds it.
}

void parallel_for(unsigned threads, size_t count, const std::function<void(size_t)>& body) {
    const unsigned size = resolve_thread_count(threads);
    if (std::min<size_t>(size, count) <= 1) {
        for (size_t i = 0; i < count; ++i) body(i);
        return;
    }
    std::shared_ptr<ThreadPool> pool;
    {
        std::lock_guard lock(pool_mutex);
        // render_pool(), unless it has another size: then it is not created for nothing.
        if (!shared_pool && size == resolve_thread_count(0)) shared_pool = std::make_shared<ThreadPool>(size);
        if (shared_pool && shared_pool->size() == size) pool = shared_pool;
    }
    if (!pool) pool = std::make_shared<ThreadPool>(unsigned(std::min<size_t>(size, count)));
    pool->parallel_for(count, body);
}

}  // namespace rt
