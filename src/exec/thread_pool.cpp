// facet exec: the worker pool behind every parallel stage (vertex, front end, tiles).
#include "facet/detail/thread_pool.hpp"

#include "facet/defaults.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace facet::detail {
namespace {

// A draw is several parallel loops in a row (vertices, front end, tiles), each a few hundred
// microseconds to a few milliseconds long, and waking a sleeping thread takes tens of microseconds
// (a futex call, more in a virtual machine). So a worker that finishes a loop, and the caller waiting
// for the last worker, first spin this long for the next event, and only then sleep. Measured with
// a spin of about this length (2-7% faster 2-thread mesh frames); when draws stop, each worker
// spends this much CPU once before it sleeps.
constexpr auto k_spin_time = std::chrono::microseconds(400);

void pause() {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
}

// Spins until done() or k_spin_time has passed; true when done.
template <class Done>
bool spin_until(const Done& done) {
    const auto until = std::chrono::steady_clock::now() + k_spin_time;
    for (;;) {
        for (int i = 0; i < 16; ++i) {
            if (done()) return true;
            pause();
        }
        if (std::chrono::steady_clock::now() >= until) return done();
    }
}

}  // namespace

struct ThreadPool::State {
    int size = 1;
    std::vector<std::thread> threads;
    std::mutex mutex;
    std::condition_variable wake, finished;
    std::atomic<std::uint64_t> generation{0};  // bumped (under the mutex) for each parallel_for
    bool stopping = false;
    std::atomic<int> busy{0};                   // workers still inside the current loop

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
            spin_until([&] { return generation.load(std::memory_order_relaxed) != seen; });
            {
                // The loop's fields were set under the mutex: taking it makes them visible.
                std::unique_lock lock(mutex);
                wake.wait(lock, [&] { return stopping || generation.load(std::memory_order_relaxed) != seen; });
                if (stopping) return;
                seen = generation.load(std::memory_order_relaxed);
            }
            run_tasks(worker);
            if (busy.fetch_sub(1, std::memory_order_acq_rel) == 1) {
                std::lock_guard lock(mutex);  // the caller tests `busy` under it: no lost wake-up
                finished.notify_one();
            }
        }
    }
};

ThreadPool::ThreadPool(int threads) : state_(std::make_unique<State>()) {
    threads = resolve_threads(threads);
    state_->size = threads;
    for (int i = 1; i < threads; ++i) state_->threads.emplace_back([s = state_.get(), i] { s->worker_loop(i); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(state_->mutex);
        state_->stopping = true;
        // Ends the workers' spin at once: they would otherwise spin out k_spin_time before they
        // see `stopping`, and the caller wait for them in join (a pool that ends with its call,
        // as the loaders' and the PNG encoder's do, paid it each time).
        state_->generation.fetch_add(1, std::memory_order_relaxed);
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
        s.busy.store(static_cast<int>(s.threads.size()), std::memory_order_relaxed);
        s.generation.fetch_add(1, std::memory_order_relaxed);
    }
    s.wake.notify_all();
    s.run_tasks(0);
    spin_until([&] { return s.busy.load(std::memory_order_acquire) == 0; });
    std::exception_ptr error;
    {
        std::unique_lock lock(s.mutex);
        s.finished.wait(lock, [&] { return s.busy.load(std::memory_order_acquire) == 0; });
        error = s.error;
        s.task = {};
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace facet::detail
