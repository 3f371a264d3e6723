// facet internals: a small fixed pool of worker threads for data-parallel loops. The calling thread
// takes part, so a pool of size 1 runs everything inline with no thread at all.
#pragma once

#include <cstddef>
#include <memory>

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
    template <class F>
    void parallel_for(std::size_t count, const F& task) {
        run(count, TaskRef{&task, [](const void* f, std::size_t i) { (*static_cast<const F*>(f))(i); }});
    }

    struct TaskRef {
        const void* callable;
        void (*call)(const void* callable, std::size_t i);
        void operator()(std::size_t i) const { call(callable, i); }
    };

private:
    void run(std::size_t count, TaskRef task);

    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace facet::detail
