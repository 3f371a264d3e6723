// facet exec: the worker pool behind every parallel stage (vertex, front end, tiles).
#include "facet/detail/thread_pool.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace facet::detail {

struct ThreadPool::State {
    int size = 1;
    std::vector<std::thread> threads;
    std::mutex mutex;
    std::condition_variable wake, finished;
    std::uint64_t generation = 0;  // bumped for each parallel_for
    bool stopping = false;
    int busy = 0;                  // workers still inside the current loop

    ThreadPool::TaskRef task{};
    std::size_t count = 0;
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr error;

    void run_tasks(int worker) {
        for (;;) {
            std::size_t i = next.fetch_add(1, std::memory_order_relaxed);
            if (i >= count || failed.load(std::memory_order_relaxed)) return;
            try {
                task(i, worker);
            } catch (...) {
                std::lock_guard lock(mutex);
                if (!error) error = std::current_exception();
                failed = true;
            }
        }
    }

    void worker_loop(int worker) {
        std::uint64_t seen = 0;
        for (;;) {
            {
                std::unique_lock lock(mutex);
                wake.wait(lock, [&] { return stopping || generation != seen; });
                if (stopping) return;
                seen = generation;
            }
            run_tasks(worker);
            std::lock_guard lock(mutex);
            if (--busy == 0) finished.notify_one();
        }
    }
};

ThreadPool::ThreadPool(int threads) : state_(std::make_unique<State>()) {
    if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    state_->size = threads;
    for (int i = 1; i < threads; ++i) state_->threads.emplace_back([s = state_.get(), i] { s->worker_loop(i); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(state_->mutex);
        state_->stopping = true;
    }
    state_->wake.notify_all();
    for (std::thread& t : state_->threads) t.join();
}

int ThreadPool::size() const { return state_->size; }

void ThreadPool::run(std::size_t count, TaskRef task) {
    State& s = *state_;
    if (count == 0) return;
    if (s.threads.empty() || count == 1) {
        for (std::size_t i = 0; i < count; ++i) task(i, 0);
        return;
    }
    {
        std::lock_guard lock(s.mutex);
        s.task = task;
        s.count = count;
        s.next = 0;
        s.failed = false;
        s.error = nullptr;
        s.busy = static_cast<int>(s.threads.size());
        ++s.generation;
    }
    s.wake.notify_all();
    s.run_tasks(0);
    std::exception_ptr error;
    {
        std::unique_lock lock(s.mutex);
        s.finished.wait(lock, [&] { return s.busy == 0; });
        error = s.error;
        s.task = {};
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace facet::detail
