// facet internals: a small fixed pool of worker threads for data-parallel loops. The calling thread
// takes part, so a pool of size 1 runs everything inline with no thread at all.
#pragma once

#include <cstddef>
#include <memory>
#include <type_traits>

#include "facet/api.hpp"

FACET_API_BEGIN
namespace facet::detail {

class ThreadPool {
public:
    explicit ThreadPool(int threads);  // total workers, the caller included; <= 0 means all cores
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int size() const;

    // Runs task(i) for every i in [0, count), spread over the workers, and returns when all are
    // done. If tasks throw, the remaining ones are skipped and the first exception is rethrown here.
    // The task is referred to, not copied: no allocation per call, unlike a std::function of a lambda
    // with a few captures (drawing allocates nothing in steady state).
    // A task may also take the index of the worker running it, task(i, worker), worker in
    // [0, size()): 0 is the calling thread. No two tasks run on one worker at once, so per-worker
    // scratch memory indexed by it needs no lock.
    template <class F>
    void parallel_for(std::size_t count, const F& task) {
        run(count, task_ref(task), DoneRef{});
    }

    // parallel_for, and then each worker that ran some of its tasks calls done(worker) once, after its
    // last one and before the loop returns (also when a task threw; done must not throw): for what a
    // worker does once per loop rather than after every task (the tile pass fences its streaming
    // stores there).
    template <class F, class G>
    void parallel_for(std::size_t count, const F& task, const G& done) {
        run(count, task_ref(task), DoneRef{&done, [](const void* g, int worker) { (*static_cast<const G*>(g))(worker); }});
    }

    // parallel_for (with or without done) that first gives each worker its own share of the
    // indices: worker w runs the w-th of size() contiguous, nearly equal ranges of [0, count) in
    // order, and a worker whose share is done takes the others' remaining tasks from their ends,
    // one at a time. For loops whose consecutive tasks use data that the same thread wrote or read
    // in the loop before (a draw's vertex blocks, then the front end's chunks of the triangles that
    // use them): on two cores each line fetched from the other core's cache costs about as much as
    // the work on it. Tasks must not wait for one another.
    template <class F>
    void parallel_for_shares(std::size_t count, const F& task) {
        run(count, task_ref(task), DoneRef{}, true);
    }
    template <class F, class G>
    void parallel_for_shares(std::size_t count, const F& task, const G& done) {
        run(count, task_ref(task), DoneRef{&done, [](const void* g, int worker) { (*static_cast<const G*>(g))(worker); }},
            true);
    }

    struct TaskRef {
        const void* callable;
        void (*call)(const void* callable, std::size_t i, int worker);
        void operator()(std::size_t i, int worker) const { call(callable, i, worker); }
    };
    struct DoneRef {
        const void* callable = nullptr;
        void (*call)(const void* callable, int worker) = nullptr;
        void operator()(int worker) const {
            if (call) call(callable, worker);
        }
    };

private:
    template <class F>
    static TaskRef task_ref(const F& task) {
        return {&task, [](const void* f, std::size_t i, int worker) {
                    if constexpr (std::is_invocable_v<const F&, std::size_t, int>)
                        (*static_cast<const F*>(f))(i, worker);
                    else
                        (*static_cast<const F*>(f))(i);
                }};
    }
    void run(std::size_t count, TaskRef task, DoneRef done, bool shares = false);

    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace facet::detail
FACET_API_END
