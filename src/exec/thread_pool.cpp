// facet exec: the worker pool behind every parallel stage (vertex, front end, tiles), and the
// threads that pools which ended leave to the next (a process starts each thread once).
#include "facet/detail/thread_pool.hpp"

#include <pthread.h>

#include "facet/defaults.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
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
    std::mutex mutex;
    std::condition_variable wake, finished, left;
    int attached = 0;  // workers in worker_loop, or on their way to it (under the mutex)
    std::atomic<std::uint64_t> generation{0};  // bumped (under the mutex) for each parallel_for
    bool stopping = false;
    std::atomic<int> busy{0};                   // workers still inside the current loop

    ThreadPool::TaskRef task{};
    ThreadPool::DoneRef done{};
    std::size_t count = 0;
    bool by_shares = false;  // parallel_for_shares
    std::atomic<bool> failed{false};
    std::exception_ptr error;
    // The next task of parallel_for, on a line of its own: each worker's fetch_add takes the line
    // from the other's cache, and the fields above, read at every task, would go with it.
    alignas(64) std::atomic<std::size_t> next{0};
    // parallel_for_shares: worker w's remaining tasks [low 32 bits, high 32 bits), a line each.
    struct alignas(64) Share {
        std::atomic<std::uint64_t> span{0};
    };
    std::unique_ptr<Share[]> shares;
    static constexpr std::uint64_t k_low = 0xffffffffu;

    // The next task of worker w's share, from its front (`own`) or its back; false when none is left.
    bool take(Share& share, bool own, std::size_t& i) {
        std::uint64_t v = share.span.load(std::memory_order_relaxed);
        for (;;) {
            const std::uint64_t front = v & k_low, back = v >> 32;
            if (front >= back) return false;
            const std::uint64_t taken = own ? v + 1 : ((back - 1) << 32 | front);
            if (share.span.compare_exchange_weak(v, taken, std::memory_order_relaxed)) {
                i = static_cast<std::size_t>(own ? front : back - 1);
                return true;
            }
        }
    }
    bool next_task(int worker, std::size_t& i) {
        if (!by_shares) {
            i = next.fetch_add(1, std::memory_order_relaxed);
            return i < count;
        }
        if (take(shares[static_cast<std::size_t>(worker)], true, i)) return true;
        for (int k = 1; k < size; ++k)
            if (take(shares[static_cast<std::size_t>((worker + k) % size)], false, i)) return true;
        return false;
    }

    // The loop's tasks this worker takes, then `done` if it took one.
    void run_tasks(int worker) {
        for (bool ran = false;; ran = true) {
            std::size_t i;
            if (!next_task(worker, i) || failed.load(std::memory_order_relaxed)) {
                if (ran) done(worker);
                return;
            }
            try {
                task(i, worker);
            } catch (...) {
                std::lock_guard lock(mutex);
                if (!error) error = std::current_exception();
                failed = true;
            }
        }
    }

    // A thread of no pool at the moment, waiting for one: a process makes pools one after another
    // (the reader's, the renderer's, the PNG encoder's; a serving worker's for each object), and
    // starting a thread, and waking it the first time, cost more than a small pool's loop.
    struct Seat {
        State* pool = nullptr;  // set (under Spare::mutex) when a pool takes the thread
        int worker = 0;
    };
    struct Spare {
        std::mutex mutex;
        std::condition_variable wake;
        std::vector<Seat*> idle;
        Spare* before_fork = nullptr;  // the parent's, kept (reachable) in a forked child
    };
    static Spare& spare();
    // A thread's life: waits for a pool, works for it until the pool ends, and waits again.
    static void serve(Seat* seat);

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

namespace {

// More than this many spare threads end instead of waiting (a pool of many threads, once).
std::size_t max_idle() { return std::max(4u, 2 * std::thread::hardware_concurrency()); }

}  // namespace

ThreadPool::State::Spare& ThreadPool::State::spare() {
    // Never destroyed: spare threads wait here when the process exits (they are detached), and a
    // forked child, which has none of the parent's threads, starts with a new one (the old one's
    // mutex may have been held by one of them).
    static Spare* current = [] {
        pthread_atfork(nullptr, nullptr, [] {
            Spare* fresh = new Spare;
            fresh->before_fork = current;
            current = fresh;
        });
        return new Spare;
    }();
    return *current;
}

void ThreadPool::State::serve(Seat* seat) {
    for (;;) {
        State* pool;
        int worker;
        {
            Spare& s = spare();
            std::unique_lock lock(s.mutex);
            s.wake.wait(lock, [&] { return seat->pool != nullptr; });
            pool = seat->pool;
            worker = seat->worker;
        }
        pool->worker_loop(worker);
        bool stay;
        {
            Spare& s = spare();
            std::lock_guard lock(s.mutex);
            seat->pool = nullptr;
            stay = s.idle.size() < max_idle();
            if (stay) s.idle.push_back(seat);
        }
        {
            // The pool's destructor waits for this; `pool` is not touched after.
            std::lock_guard lock(pool->mutex);
            if (--pool->attached == 0) pool->left.notify_all();
        }
        if (!stay) {
            delete seat;
            return;
        }
    }
}

ThreadPool::ThreadPool(int threads) : state_(std::make_unique<State>()) {
    threads = resolve_threads(threads);
    state_->size = threads;
    state_->shares = std::make_unique<State::Share[]>(static_cast<std::size_t>(threads));
    state_->attached = threads - 1;
    State::Spare& s = State::spare();
    bool woke = false;
    for (int i = 1; i < threads; ++i) {
        {
            std::lock_guard lock(s.mutex);
            if (!s.idle.empty()) {
                State::Seat* seat = s.idle.back();
                s.idle.pop_back();
                seat->pool = state_.get();
                seat->worker = i;
                woke = true;
                continue;
            }
        }
        auto* seat = new State::Seat{state_.get(), i};
        try {
            std::thread([seat] { State::serve(seat); }).detach();
        } catch (...) {  // no more threads: the pool has the ones it got
            delete seat;
            std::lock_guard lock(state_->mutex);
            state_->size = i;
            state_->attached = i - 1;
            break;
        }
    }
    if (woke) s.wake.notify_all();
}

ThreadPool::~ThreadPool() {
    std::unique_lock lock(state_->mutex);
    state_->stopping = true;
    // Ends the workers' spin at once: they would otherwise spin out k_spin_time before they see
    // `stopping`, and the destructor wait for them (a pool that ends with its call, as the
    // loaders' and the PNG encoder's do, paid it each time).
    state_->generation.fetch_add(1, std::memory_order_relaxed);
    state_->wake.notify_all();
    state_->left.wait(lock, [&] { return state_->attached == 0; });
}

int ThreadPool::size() const { return state_->size; }

void ThreadPool::run(std::size_t count, TaskRef task, DoneRef done, bool shares) {
    State& s = *state_;
    if (count == 0) return;
    if (s.size == 1 || count == 1) {
        struct Done {  // also when a task throws
            const DoneRef& done;
            ~Done() { done(0); }
        } at_end{done};
        for (std::size_t i = 0; i < count; ++i) task(i, 0);
        return;
    }
    {
        std::lock_guard lock(s.mutex);
        s.task = task;
        s.done = done;
        s.count = count;
        s.next = 0;
        // Shares of a loop of 2^32 tasks or more would not fit their halves of a word.
        s.by_shares = shares && count <= State::k_low;
        if (s.by_shares) {
            const auto n = static_cast<std::uint64_t>(s.size);
            for (std::uint64_t w = 0; w < n; ++w)
                s.shares[w].span.store(count * (w + 1) / n << 32 | count * w / n, std::memory_order_relaxed);
        }
        s.failed = false;
        s.error = nullptr;
        s.busy.store(s.size - 1, std::memory_order_relaxed);
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
        s.done = {};
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace facet::detail
