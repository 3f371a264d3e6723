// facet benchmarks: model loading, facet's own readers against the assimp path, in alternating
// rounds (the machine's load hits both alike). Not a stage of the renderer.
// Usage: facet_bench_load FILE [ROUNDS] [THREADS]  (defaults 5 rounds, 1 thread)
// Prints per path the median wall time of load_model (file to Scene, normals included) and the ratio,
// and the same of the loading process's CPU time (user + system of all its threads: on a shared machine it
// moves far less with the load than wall time). FACET_BENCH_LOAD_OWN_ONLY=1 runs the own reader alone
// (for profilers: callgrind, perf; callgrind writes each round's child to a file of its own).
// Each load runs in a child forked for it with the heap `facet render`'s worker sets up before it
// loads (keep_freed_memory_for_reuse, and use_huge_pages_for_heap for the files that get it): a
// user's load is one per fresh process, not a loop's later rounds reusing what an earlier one freed.
// FACET_BENCH_LOAD_PAUSE_MS=N sleeps N ms before each child (memory freed seconds ago is slow to fault
// in again on this VM: docs/BENCHMARKS.md "Loading OBJ, session 12"); FACET_BENCH_LOAD_ROUNDS=1 prints
// each child's wall and CPU ms and page faults to stderr, and the median faults go into the JSON.
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "facet/model.hpp"
#include "io/load_paths.hpp"
#if FACET_BENCH_LOAD_WORKER_HEAP  // without the command line's library (FACET_BUILD_APPS off): a plain heap
#include "worker.hpp"
#endif

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

long page_faults() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_minflt + usage.ru_majflt;
}

struct Round {
    double ms = 0, cpu_ms = 0, faults = 0;
    std::size_t triangles = 0;
    bool ok = false;
};

// One load in a child process set up as the worker is (apps/cli/render_command.cpp: the same for
// both paths, which depends on the file's extension alone).
Round load_in_child(const std::string& path, const facet::LoadOptions& options, bool own) {
    Round round;
    int fds[2];
    if (pipe(fds) != 0) return round;
    const pid_t pid = fork();
    if (pid < 0) return round;
    if (pid == 0) {
        close(fds[0]);
#if FACET_BENCH_LOAD_WORKER_HEAP
        facet::cli::keep_freed_memory_for_reuse();
        if (facet::cli::huge_pages_suit(path)) facet::cli::use_huge_pages_for_heap(0);
#endif
        facet::LoadOptions in_worker = options;
        in_worker.map_files = true;  // as the worker loads (apps/cli/render_command.cpp)
        const Clock::time_point start = Clock::now();
        const double cpu_start = process_cpu_ms();
        const long faults_start = page_faults();
        facet::Result<facet::LoadedModel> model =
            own ? facet::load_model(path, in_worker) : facet::io_detail::load_model_through_assimp(path, in_worker);
        Round r;
        r.ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        r.cpu_ms = process_cpu_ms() - cpu_start;
        r.faults = static_cast<double>(page_faults() - faults_start);
        if (model) {
            r.ok = true;
            r.triangles = model->scene.triangle_count();
        } else {
            std::fprintf(stderr, "facet_bench_load: %s\n", model.error().message.c_str());
        }
        const bool written = write(fds[1], &r, sizeof r) == static_cast<ssize_t>(sizeof r);
        _exit(written && r.ok ? 0 : 1);  // the model is not freed: a worker exits with it
    }
    close(fds[1]);
    const bool read_all = read(fds[0], &round, sizeof round) == static_cast<ssize_t>(sizeof round);
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (!read_all || !WIFEXITED(status) || WEXITSTATUS(status) != 0) round.ok = false;
    return round;
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
    std::vector<double> own, assimp, own_cpu, assimp_cpu, own_faults, assimp_faults;
    std::size_t triangles = 0;
    const char* own_only_env = std::getenv("FACET_BENCH_LOAD_OWN_ONLY");
    const bool own_only = own_only_env && std::string(own_only_env) == "1";
    const char* pause_env = std::getenv("FACET_BENCH_LOAD_PAUSE_MS");
    const int pause_ms = pause_env ? std::max(0, std::atoi(pause_env)) : 0;
    const char* rounds_env = std::getenv("FACET_BENCH_LOAD_ROUNDS");
    const bool print_rounds = rounds_env && std::string(rounds_env) == "1";
    // The readers' module opened before the children are forked, as `facet thumbs` does for its
    // workers: the loads measure the readers, not the module's opening and relocation (the 1M sphere:
    // 2-4 ms, paid once per `facet render` process).
    (void)facet::open_model_reader_module();
    for (int r = 0; r < rounds; ++r) {
        for (int which = 0; which < (own_only ? 1 : 2); ++which) {
            if (pause_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(pause_ms));
            const Round round = load_in_child(path, options, which == 0);
            if (!round.ok) return 1;  // the child said why
            triangles = round.triangles;
            (which == 0 ? own : assimp).push_back(round.ms);
            (which == 0 ? own_cpu : assimp_cpu).push_back(round.cpu_ms);
            (which == 0 ? own_faults : assimp_faults).push_back(round.faults);
            if (print_rounds)
                std::fprintf(stderr, "%s %d: %.1f ms, %.1f ms CPU, %.0f page faults\n", which == 0 ? "own" : "assimp", r, round.ms,
                             round.cpu_ms, round.faults);
        }
    }
    if (own_only) {
        std::printf("{\"file\":\"%s\",\"triangles\":%zu,\"threads\":%d,\"rounds\":%d,\"own_ms\":%.1f,\"own_cpu_ms\":%.1f,\"own_faults\":%.0f}\n",
                    path.c_str(), triangles, options.threads, rounds, median(own), median(own_cpu), median(own_faults));
        return 0;
    }
    const double a = median(assimp), o = median(own), a_cpu = median(assimp_cpu), o_cpu = median(own_cpu);
    std::printf("{\"file\":\"%s\",\"triangles\":%zu,\"threads\":%d,\"rounds\":%d,\"own_ms\":%.1f,\"assimp_ms\":%.1f,\"ratio\":%.2f,"
                "\"own_cpu_ms\":%.1f,\"assimp_cpu_ms\":%.1f,\"cpu_ratio\":%.2f,\"own_faults\":%.0f,\"assimp_faults\":%.0f}\n",
                path.c_str(), triangles, options.threads, rounds, o, a, a / o, o_cpu, a_cpu, a_cpu / o_cpu, median(own_faults),
                median(assimp_faults));
    return 0;
}
