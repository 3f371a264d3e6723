// facet benchmarks: compute_creased_normals on the 1,003,520-triangle geodesic sphere (its normals
// removed), one thread, the median CPU time of the thread over rounds: on a shared machine CPU time
// moves far less with the load than wall time. Prints a checksum of the normals' bits, so that two
// builds can be compared for the same result. Not a stage of the renderer.
// Usage: facet_bench_creased [ROUNDS=5]
#include <time.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_scenes.hpp"
#include "facet/mesh.hpp"

namespace {

double thread_cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc > 2 || (argc == 2 && std::string(argv[1]) == "--help")) {
        std::printf("usage: facet_bench_creased [ROUNDS=5]\n"
                    "Times compute_creased_normals (30 degrees, 1 thread) on the 1M-triangle sphere: median thread CPU ms.\n");
        return argc == 2 ? 0 : 2;
    }
    const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
    facet::Mesh sphere = facet::bench::make_geodesic_sphere(1.0f, facet::bench::k_million_sphere_frequency);
    sphere.normals.clear();
    std::vector<double> ms;
    std::uint64_t checksum = 0;
    for (int r = 0; r < rounds; ++r) {
        facet::Mesh m = sphere;
        const double start = thread_cpu_ms();
        facet::compute_creased_normals(m, facet::radians(30.0f), 1);
        ms.push_back(thread_cpu_ms() - start);
        checksum = 0;
        for (const facet::Vec3& n : m.normals)
            checksum = checksum * 31 + std::bit_cast<std::uint32_t>(n.x) + 7 * std::bit_cast<std::uint32_t>(n.y) +
                       13 * std::bit_cast<std::uint32_t>(n.z);
    }
    std::sort(ms.begin(), ms.end());
    std::printf("{\"triangles\":%zu,\"rounds\":%d,\"cpu_ms_median\":%.1f,\"cpu_ms_min\":%.1f,\"checksum\":\"%016llx\"}\n",
                sphere.triangle_count(), rounds, ms[ms.size() / 2], ms.front(), static_cast<unsigned long long>(checksum));
}
