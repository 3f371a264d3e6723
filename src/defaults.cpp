// facet: resolving the settings whose zero means "choose for me" (facet/defaults.hpp), for the
// Renderer, the loader's normals and the command line alike.
#include "facet/defaults.hpp"

#include <algorithm>
#include <thread>

namespace facet {

int resolve_threads(int threads) {
    if (threads > 0) return threads;
    return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

std::size_t resolve_batch_triangles(int per_thread, int threads) {
    const auto t = static_cast<std::size_t>(std::max(threads, 1));
    if (per_thread > 0) return static_cast<std::size_t>(per_thread) * t;
    return std::max(defaults::k_batch_triangles_per_thread * t, defaults::k_min_batch_triangles);
}

}  // namespace facet
