// facet internals: a small fixed pool of worker threads for data-parallel loops. The calling thread
// takes part, so a pool of size 1 runs everything inline with no thread at all.
#pragma once

#include <cstddef>
#include <functional>
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
    void parallel_for(std::size_t count, const std::function<void(std::size_t)>& task);

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace facet::detail
