// The command line's heap set-up for its one-job processes (apps/cli/worker.hpp): the heap's next
// stretch is advised to use transparent huge pages, as large as asked and no larger than a quarter
// of the memory cap. Checked in a fresh process (the set-up changes the process's heap for good)
// through /proc/self/smaps, where an advised region's VmFlags show "hg". Also a thumbs worker's
// first job (thumbnail_job.hpp) whose load runs out of memory: its heap is advised all the same.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "options.hpp"
#include "support/paths.hpp"
#include "thumbnail_job.hpp"
#include "worker.hpp"

namespace {

// The total size of this process's regions advised for huge pages (VmFlags "hg"), in bytes, and
// whether `at` lies in one of them.
std::uint64_t advised_bytes(const void* at = nullptr, bool* at_advised = nullptr) {
    std::ifstream smaps("/proc/self/smaps");
    std::uint64_t total = 0, size_kb = 0;
    bool holds_at = false;
    for (std::string line; std::getline(smaps, line);) {
        std::istringstream fields(line);
        std::string key;
        fields >> key;
        if (const std::size_t dash = key.find('-'); dash != std::string::npos && key.find(':') == std::string::npos) {
            // A region's first line: "start-end perms ...".
            const auto start = std::stoull(key.substr(0, dash), nullptr, 16), end = std::stoull(key.substr(dash + 1), nullptr, 16);
            const auto a = reinterpret_cast<std::uintptr_t>(at);
            holds_at = at && a >= start && a < end;
        }
        if (key == "Size:") fields >> size_kb;
        if (key == "VmFlags:")
            for (std::string flag; fields >> flag;)
                if (flag == "hg") {
                    total += size_kb << 10;
                    if (holds_at && at_advised) *at_advised = true;
                }
    }
    return total;
}

// The set-up and what it advised beyond what was advised before, reported on `fd`; then whether a
// job's first large buffer (the bunny's file is 2.6 MB) is carved from the advised range.
[[noreturn]] void measure_setup(std::uint64_t cap, int fd) {
    const std::uint64_t before = advised_bytes();
    facet::cli::keep_freed_memory_for_reuse();
    facet::cli::use_huge_pages_for_heap(cap);
    const std::uint64_t grown = advised_bytes() - before;
    void* const first_buffer = std::malloc(std::size_t{5} << 19);
    bool buffer_advised = false;
    advised_bytes(first_buffer, &buffer_advised);
    const std::uint64_t report[2] = {grown, buffer_advised};
    (void)!write(fd, report, sizeof report);
    std::free(first_buffer);
    _exit(0);
}

// A thumbs worker's first job, under the worker's memory cap `cap`, on a file assimp reads, so that
// the heap is advised once the file is loaded (ThumbnailJob::huge_heap_after_load), as thumbs gives
// it; reported on `fd`: the job's exit status, what it advised, and whether it failed for memory.
[[noreturn]] void measure_failed_job(std::uint64_t cap, int fd, const char* model) {
    facet::cli::keep_freed_memory_for_reuse();
    const rlimit limit{cap, cap};  // as run_in_worker caps a worker's memory
    setrlimit(RLIMIT_AS, &limit);
    const std::uint64_t before = advised_bytes();
    std::uint64_t report[3] = {~0ull, 0, 0};
    int messages[2];
    if (facet::Result<facet::cli::RenderPlan> plan = facet::cli::make_plan({}, false); plan && pipe(messages) == 0) {
        facet::cli::ThumbnailJob job{.model = model, .plan = *plan, .output = "/nonexistent/thumbnail.png"};
        job.confine = false;
        job.huge_heap_after_load = cap;
        report[0] = static_cast<std::uint64_t>(facet::cli::run_thumbnail_job(job, facet::cli::WorkerReport(messages[1])));
        report[1] = advised_bytes() - before;
        close(messages[1]);
        std::string text(4096, '\0');  // the job's report: a phase, its figures, its error
        const ssize_t n = read(messages[0], text.data(), text.size());
        text.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
        report[2] = text.find("needs more memory than is available") != std::string::npos;
    }
    (void)!write(fd, report, sizeof report);
    _exit(0);
}

// In the process in_fresh_process starts: measure before any test runs, then exit.
const bool g_measuring_child = [] {
    const char* spec = std::getenv("FACET_HEAP_TEST_CHILD");
    unsigned long long cap = 0;
    int fd = -1;
    if (spec && std::sscanf(spec, "%llu,%d", &cap, &fd) == 2) {
        if (const char* model = std::getenv("FACET_HEAP_TEST_MODEL")) measure_failed_job(cap, fd, model);
        measure_setup(cap, fd);
    }
    return false;
}();

// Runs this test binary again with FACET_HEAP_TEST_CHILD (and FACET_HEAP_TEST_MODEL when `model` is
// given), which measures in a static initialiser, and returns its report. Fresh, as a job process
// is: a process that has run other tests has free chunks in its heap large enough for the set-up's
// block, and then nothing grows.
template <std::size_t N>
std::array<std::uint64_t, N> in_fresh_process(std::uint64_t cap, const char* model = nullptr) {
    std::array<std::uint64_t, N> report;
    report.fill(~0ull);
    int fds[2];
    if (pipe(fds) != 0) return report;
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        const std::string spec = std::to_string(cap) + "," + std::to_string(fds[1]);
        setenv("FACET_HEAP_TEST_CHILD", spec.c_str(), 1);
        if (model) setenv("FACET_HEAP_TEST_MODEL", model, 1);
        const int null = open("/dev/null", O_WRONLY);
        dup2(null, STDOUT_FILENO);
        dup2(null, STDERR_FILENO);
        char self[] = "/proc/self/exe";
        char* const args[] = {self, nullptr};
        execv(self, args);
        _exit(127);
    }
    close(fds[1]);
    if (read(fds[0], report.data(), sizeof report) != sizeof report) report.fill(~0ull);
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return report;
}

// The set-up with `cap` in a fresh process: what it advised.
std::uint64_t advised_by_setup(std::uint64_t cap, bool* buffer_advised = nullptr) {
    const auto report = in_fresh_process<2>(cap);
    if (buffer_advised) *buffer_advised = report[1] == 1;
    return report[0];
}

TEST(CliHeap, TheHeapIsGrownInHugePagesWithinAQuarterOfTheMemoryCap) {
    // Sanitizer builds, where there is no memory cap, have their own allocator, not glibc's brk heap.
    if (!facet::cli::memory_cap_supported()) GTEST_SKIP() << "a sanitizer's allocator, not glibc's heap";
    if (!std::filesystem::exists("/sys/kernel/mm/transparent_hugepage"))
        GTEST_SKIP() << "this kernel has no transparent huge pages";
    constexpr std::uint64_t mib = 1 << 20;
    // No cap: 128 MiB, less the partial huge pages at the two ends of the grown range.
    bool buffer_advised = false;
    const std::uint64_t uncapped = advised_by_setup(0, &buffer_advised);
    EXPECT_GE(uncapped, 124 * mib);
    EXPECT_LE(uncapped, 130 * mib);
    // The job's buffers come from the advised range, not from the 4 KiB pages below it (up to
    // 2 MiB, where the heap happened to end).
    EXPECT_TRUE(buffer_advised);
    // A 64 MiB cap: 16 MiB at most.
    const std::uint64_t capped = advised_by_setup(64 * mib);
    EXPECT_GE(capped, 12 * mib);
    EXPECT_LE(capped, 18 * mib);
}

// A thumbs worker goes on to its next jobs after a first job whose load failed, so the heap that
// job was to advise once its file was loaded must be advised also when the load ran out of memory.
// (The load's std::bad_alloc becomes an error inside load_model; run_thumbnail_job's own
// bad_alloc handler, which advises too, is not reached this way: docs/RELIABILITY.md.)
TEST(CliHeap, AThumbsWorkersFirstJobAdvisesTheHeapAlsoWhenItsLoadRunsOutOfMemory) {
    if (!facet::cli::memory_cap_supported()) GTEST_SKIP() << "a sanitizer's allocator: no memory cap";
    if (!std::filesystem::exists("/sys/kernel/mm/transparent_hugepage"))
        GTEST_SKIP() << "this kernel has no transparent huge pages";
    // A COB file whose header makes assimp ask for more than 1 GiB (tests/regression/assimp_crashes).
    const std::filesystem::path model =
        std::filesystem::path(facet_test::k_source_dir) / "tests/regression/assimp_crashes/cob_out-of-memory_570cd280.cob";
    ASSERT_TRUE(std::filesystem::is_regular_file(model)) << model;
    constexpr std::uint64_t mib = 1 << 20;
    const auto report = in_fresh_process<3>(1024 * mib, model.c_str());
    EXPECT_EQ(report[0], static_cast<std::uint64_t>(facet::cli::k_exit_failed));
    EXPECT_EQ(report[2], 1u) << "the load did not fail for memory";
    // min(128 MiB, a quarter of the cap), less the partial huge pages at the two ends.
    EXPECT_GE(report[1], 124 * mib);
    EXPECT_LE(report[1], 130 * mib);
}

}  // namespace
