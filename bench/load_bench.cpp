// facet benchmarks: model loading, facet's own readers against the assimp path, in one process and
// alternating rounds (the machine's load hits both alike). Not a stage of the renderer.
// Usage: facet_bench_load FILE [ROUNDS] [THREADS]  (defaults 5 rounds, 1 thread)
// Prints per path the median wall time of load_model (file to Scene, normals included) and the ratio,
// and the same of the process's CPU time (user + system of all its threads: on a shared machine it
// moves far less with the load than wall time). FACET_BENCH_LOAD_OWN_ONLY=1 runs the own reader alone
// (for profilers: callgrind, perf).
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "facet/model.hpp"
#include "io/load_paths.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double process_cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argc > 4 || std::string(argv[1]) == "--help") {
        std::printf("usage: facet_bench_load FILE [ROUNDS=5] [THREADS=1]\n"
                    "Loads FILE through facet's own reader (load_model) and through assimp, alternating, and prints\n"
                    "the median milliseconds of each and their ratio.\n");
        return argc >= 2 ? 0 : 2;
    }
    const std::string path = argv[1];
    const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
    facet::LoadOptions options;
    options.threads = argc > 3 ? std::atoi(argv[3]) : 1;
    std::vector<double> own, assimp, own_cpu, assimp_cpu;
    std::size_t triangles = 0;
    const char* own_only_env = std::getenv("FACET_BENCH_LOAD_OWN_ONLY");
    const bool own_only = own_only_env && std::string(own_only_env) == "1";
    for (int r = 0; r < rounds; ++r) {
        for (int which = 0; which < (own_only ? 1 : 2); ++which) {
            const Clock::time_point start = Clock::now();
            const double cpu_start = process_cpu_ms();
            facet::Result<facet::LoadedModel> model =
                which == 0 ? facet::load_model(path, options) : facet::io_detail::load_model_through_assimp(path, options);
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
            (which == 0 ? own_cpu : assimp_cpu).push_back(process_cpu_ms() - cpu_start);
            if (!model) {
                std::fprintf(stderr, "facet_bench_load: %s\n", model.error().message.c_str());
                return 1;
            }
            triangles = model->scene.triangle_count();
            (which == 0 ? own : assimp).push_back(ms);
        }
    }
    if (own_only) {
        std::printf("{\"file\":\"%s\",\"triangles\":%zu,\"threads\":%d,\"rounds\":%d,\"own_ms\":%.1f,\"own_cpu_ms\":%.1f}\n", path.c_str(),
                    triangles, options.threads, rounds, median(own), median(own_cpu));
        return 0;
    }
    const double a = median(assimp), o = median(own), a_cpu = median(assimp_cpu), o_cpu = median(own_cpu);
    std::printf("{\"file\":\"%s\",\"triangles\":%zu,\"threads\":%d,\"rounds\":%d,\"own_ms\":%.1f,\"assimp_ms\":%.1f,\"ratio\":%.2f,"
                "\"own_cpu_ms\":%.1f,\"assimp_cpu_ms\":%.1f,\"cpu_ratio\":%.2f}\n",
                path.c_str(), triangles, options.threads, rounds, o, a, a / o, o_cpu, a_cpu, a_cpu / o_cpu);
    return 0;
}
