// `facet render` runs its job in a worker process (apps/cli/worker.hpp): files that crash, hang or
// exhaust memory inside the model reader (assimp) end in exit status 1, one line naming the file
// and the reason, and no output file, instead of a crash of facet (docs/RELIABILITY.md).
//
// The inputs in tests/regression/assimp_crashes/ were found by fuzz/load_model_fuzzer and crash
// Debian's libassimp 5.2.5 itself; their names say the format and what assimp does with them
// (segv, bus, double-free, out-of-memory, hang). They must never be given to load_model in the
// test process.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "support/cli.hpp"
#include "support/paths.hpp"
#include "support/test_data.hpp"
#include "worker.hpp"

namespace {

namespace fs = std::filesystem;
using facet_test::k_box_obj;
using facet_test::ScopedEnv;
using facet_test::CliRun;
using facet_test::run_facet;
using facet_test::write_text;

const fs::path k_crash_dir = fs::path(facet_test::k_source_dir) / "tests" / "regression" / "assimp_crashes";

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
// A sanitizer catches the reader's crash in the worker itself, reports it and exits with the test
// presets' exitcode=99, which facet passes on; and the memory cap is off (RLIMIT_DATA would count
// the sanitizers' shadow memory).
constexpr bool k_sanitized = true;
#else
constexpr bool k_sanitized = false;
#endif

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::vector<std::string> files_in(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// The crash inputs, in name order; with `hanging`, only the one that hangs assimp, else all others.
std::vector<fs::path> crash_inputs(bool hanging) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(k_crash_dir))
        if (contains(e.path().filename().string(), "_hang_") == hanging) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

// Under a sanitizer the memory cap is off; its allocator refusing allocations over 1 GiB instead
// (returning null, so operator new throws as under the cap) keeps the out-of-memory inputs from
// taking gigabytes. Set for the whole test: a no-op in other builds.
std::string with_allocation_cap(const char* variable) {
    const char* old = std::getenv(variable);
    return std::string(old ? old : "") + ":allocator_may_return_null=1:max_allocation_size_mb=1024";
}

TEST(RenderIsolation, EveryInputThatCrashesTheReaderFailsWithOneNamingTheFileAndWritesNothing) {
    const ScopedEnv asan("ASAN_OPTIONS", with_allocation_cap("ASAN_OPTIONS"));
    const ScopedEnv tsan("TSAN_OPTIONS", with_allocation_cap("TSAN_OPTIONS"));
    const fs::path out_dir = facet_test::test_temp_dir("facet_isolation") / "out";
    fs::create_directories(out_dir);
    const std::vector<fs::path> inputs = crash_inputs(false);
    ASSERT_EQ(inputs.size(), 15u) << "tests/regression/assimp_crashes/ is incomplete";
    for (const fs::path& input : inputs) {
        SCOPED_TRACE(input.filename().string());
#if defined(__SANITIZE_THREAD__)
        // ThreadSanitizer's allocator does not check frees: assimp's double free goes unnoticed
        // there and the file loads (glibc aborts, ASan reports it).
        if (contains(input.filename().string(), "double-free")) continue;
#endif
        fs::remove_all(out_dir);  // one input's failure must not show up as the next one's
        fs::create_directories(out_dir);
        // The timeout is a safety net (none of these hangs), the memory cap keeps the inputs that
        // allocate without bound from taking gigabytes.
        const CliRun r = run_facet({"render", input.string(), "--size", "32x24", "-o", (out_dir / "o.png").string(),
                                    "--depth-out", (out_dir / "d.png").string(), "--timeout", "120", "--max-memory", "1G"});
        if (k_sanitized) EXPECT_TRUE(r.exit_code == 1 || r.exit_code == 99) << r.all();
        else EXPECT_EQ(r.exit_code, 1) << r.all();
        EXPECT_TRUE(contains(r.err, "facet render: " + input.string() + ": ")) << r.err;
        if (!k_sanitized) {
            // What happened, said in words: a signal the reader died of, or memory it could not get.
            EXPECT_TRUE(contains(r.err, ": the importer crashed (SIG") ||
                        contains(r.err, ": needs more memory than is available"))
                << r.err;
        }
        EXPECT_TRUE(r.out.empty()) << r.out;
        EXPECT_TRUE(fs::is_empty(out_dir)) << "left behind: " << testing::PrintToString(files_in(out_dir));
    }
}

TEST(RenderIsolation, AFileThatHangsTheReaderIsAbandonedAfterTheTimeout) {
    const std::vector<fs::path> hanging = crash_inputs(true);
    ASSERT_EQ(hanging.size(), 1u);
    const fs::path out_dir = facet_test::test_temp_dir("facet_isolation") / "out";
    fs::create_directories(out_dir);
    const CliRun r = run_facet({"render", hanging[0].string(), "--size", "32x24", "-o", (out_dir / "o.png").string(),
                                "--timeout", "1.5"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(contains(r.err, "facet render: " + hanging[0].string() + ": gave up after 1.5 s")) << r.err;
    EXPECT_TRUE(fs::is_empty(out_dir)) << "left behind: " << testing::PrintToString(files_in(out_dir));
}

// The test hook (FACET_TEST_SLEEP_ON) makes the worker of a good file hang: killed at the
// deadline, its temporary output files are removed (here one left as if the worker had been killed
// mid-write), and only those: a file that merely starts with the same name stays.
TEST(RenderIsolation, AKilledWorkerLeavesNoTemporaryFiles) {
    const fs::path dir = facet_test::test_temp_dir("facet_isolation");
    const std::string model = write_text(dir / "in" / "hangs.obj", k_box_obj);
    write_text(dir / "out" / "o.png.tmp123456", "partial");
    write_text(dir / "out" / "o.png.tmp-not-ours", "someone else's");
    const ScopedEnv hook("FACET_TEST_SLEEP_ON", "hangs");
    const CliRun r = run_facet({"render", model, "--size", "16x16", "-o", (dir / "out" / "o.png").string(), "--timeout",
                                "0.5"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(contains(r.err, model + ": gave up after 0.5 s (--timeout sets the limit)")) << r.err;
    EXPECT_EQ(files_in(dir / "out"), std::vector<std::string>{"o.png.tmp-not-ours"});
}

// The worker reports its job's status before it exits: facet returns with it (the worker's exit,
// hung here by the test hook, is not waited for: it ends with facet, PR_SET_PDEATHSIG). Sanitizer
// builds wait for the exit, whose status carries LeakSanitizer's reports.
TEST(RenderIsolation, TheJobsStatusIsReturnedWithoutWaitingForTheWorkersExit) {
    if (k_sanitized) GTEST_SKIP() << "sanitizer builds wait for the worker's exit";
    if (!facet::cli::orphans_are_reaped()) GTEST_SKIP() << "in a PID namespace of its own facet waits for the worker's exit";
    const fs::path dir = facet_test::test_temp_dir("facet_isolation");
    const std::string model = write_text(dir / "lingers.obj", k_box_obj);
    const ScopedEnv hook("FACET_TEST_LINGER_ON", "lingers");
    const CliRun r = run_facet({"render", model, "--size", "16x16", "-o", (dir / "o.png").string(), "--timeout", "20"});
    EXPECT_EQ(r.exit_code, 0) << r.all();
    const facet_test::DecodedPng png = facet_test::decode_png(dir / "o.png");
    EXPECT_TRUE(png.ok()) << png.error;
}

// In a PID namespace of its own (a container), PID 1 may be a program that never reaps the
// processes it adopts: facet then reaps its worker itself before it exits, leaving PID 1 no child.
// The test is that PID 1 (a forked child of this test, unshare(CLONE_NEWPID) needs root); it
// runs facet, waits for facet alone, and then looks for any other child.
TEST(RenderIsolation, InAPidNamespaceOfItsOwnFacetLeavesNoOrphanedWorker) {
    // They always wait; and LeakSanitizer cannot stop facet's threads there (it finds them in this
    // namespace's /proc and traces them by their IDs in the new one), so facet would fail at exit.
    if (k_sanitized) GTEST_SKIP() << "sanitizer builds wait for the worker's exit";
    const fs::path dir = facet_test::test_temp_dir("facet_isolation");
    const std::string model = write_text(dir / "box.obj", k_box_obj);
    const std::string out = (dir / "o.png").string();
    std::vector<std::string> args{facet_test::facet_binary().string(), "render", model, "--size", "16x16", "-o", out};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t outside = fork();
    ASSERT_GE(outside, 0);
    if (outside == 0) {
        if (unshare(CLONE_NEWPID) != 0) _exit(77);
        const pid_t init = fork();  // PID 1 of the new namespace
        if (init < 0) _exit(3);
        if (init == 0) {
            posix_spawn_file_actions_t actions;
            posix_spawn_file_actions_init(&actions);
            posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
            posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
            pid_t facet = -1;
            if (posix_spawn(&facet, argv[0], &actions, nullptr, argv.data(), environ) != 0) _exit(4);
            int status = 0;
            if (waitpid(facet, &status, 0) != facet || !WIFEXITED(status) || WEXITSTATUS(status) != 0) _exit(5);
            siginfo_t any{};
            const bool no_child = waitid(P_ALL, 0, &any, WEXITED | WNOHANG | WNOWAIT) != 0 && errno == ECHILD;
            _exit(no_child ? 0 : 6);
        }
        int status = 0;
        _exit(waitpid(init, &status, 0) == init && WIFEXITED(status) ? WEXITSTATUS(status) : 2);
    }
    int status = 0;
    ASSERT_EQ(waitpid(outside, &status, 0), outside);
    ASSERT_TRUE(WIFEXITED(status));
    if (WEXITSTATUS(status) == 77) GTEST_SKIP() << "unshare(CLONE_NEWPID) is not permitted here";
    EXPECT_NE(WEXITSTATUS(status), 5) << "facet render failed in the namespace";
    EXPECT_NE(WEXITSTATUS(status), 6) << "facet's worker was left to PID 1";
    EXPECT_EQ(WEXITSTATUS(status), 0);
    EXPECT_TRUE(facet_test::decode_png(out).ok());
}

// --no-isolation runs the job in facet's own process: the test hook, which lives in the worker,
// does not fire, and the image is the same byte for byte.
TEST(RenderIsolation, NoIsolationRendersTheSameImageInProcess) {
    const fs::path dir = facet_test::test_temp_dir("facet_isolation");
    const std::string model = write_text(dir / "hangs.obj", k_box_obj);
    const CliRun isolated = run_facet({"render", model, "--size", "40x30", "-o", (dir / "a.png").string()});
    ASSERT_EQ(isolated.exit_code, 0) << isolated.all();
    const ScopedEnv hook("FACET_TEST_SLEEP_ON", "hangs");
    const CliRun in_process = run_facet({"render", model, "--size", "40x30", "-o", (dir / "b.png").string(), "--no-isolation"});
    ASSERT_EQ(in_process.exit_code, 0) << in_process.all();
    const facet_test::DecodedPng a = facet_test::decode_png(dir / "a.png"), b = facet_test::decode_png(dir / "b.png");
    ASSERT_TRUE(a.ok() && b.ok()) << a.error << b.error;
    EXPECT_EQ(a.rgba, b.rgba);

    // The worker's limits do not apply in-process: asking for them is a usage error.
    for (const char* option : {"--timeout", "--max-memory"}) {
        const CliRun r = run_facet({"render", model, "-o", (dir / "c.png").string(), "--no-isolation", option, "10"});
        EXPECT_EQ(r.exit_code, 2) << option << ": " << r.all();
        EXPECT_TRUE(contains(r.err, "--no-isolation")) << r.err;
        EXPECT_FALSE(fs::exists(dir / "c.png"));
    }
}

TEST(RenderIsolation, TheMemoryCapStopsAReaderThatAllocatesWithoutBound) {
    if (k_sanitized) GTEST_SKIP() << "no memory cap in sanitizer builds (RLIMIT_DATA would count the shadow memory)";
    const fs::path dir = facet_test::test_temp_dir("facet_isolation");
    // Without a cap this file makes assimp take more than 10 GiB (and minutes).
    const fs::path runaway = k_crash_dir / "mdl_out-of-memory_47f6ce00.mdl";
    const CliRun r = run_facet({"render", runaway.string(), "-o", (dir / "o.png").string(), "--max-memory", "256M"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(contains(r.err, runaway.string() + ": needs more memory than is available")) << r.err;
    EXPECT_FALSE(fs::exists(dir / "o.png"));
    // The same cap leaves room for an ordinary model, drawn with several threads.
    const std::string box = write_text(dir / "box.obj", k_box_obj);
    const CliRun ok = run_facet({"render", box, "-o", (dir / "box.png").string(), "--size", "64x64", "--threads", "4",
                                 "--max-memory", "256M"});
    EXPECT_EQ(ok.exit_code, 0) << ok.all();
    EXPECT_TRUE(facet_test::decode_png(dir / "box.png").ok());
}

TEST(RenderIsolation, ARenderThatRunsOutOfMemorySaysSoNamingTheModel) {
    if (k_sanitized) GTEST_SKIP() << "no memory cap in sanitizer builds (RLIMIT_DATA would count the shadow memory)";
    const fs::path dir = facet_test::test_temp_dir("facet_isolation");
    // The default scene loads in a few MiB, but an 8000x8000 target does not fit in 64 MiB: the worker's
    // render throws std::bad_alloc. It ended with status 1 and no message.
    const CliRun r = run_facet({"render", "-o", (dir / "big.png").string(), "--size", "8000x8000", "--max-memory", "64M"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(contains(r.err, "facet render: the default scene: out of memory\n")) << r.err;
    EXPECT_FALSE(fs::exists(dir / "big.png"));
}

TEST(RenderIsolation, InvalidLimitsAreUsageErrors) {
    const fs::path dir = facet_test::test_temp_dir("facet_isolation");
    for (std::vector<std::string> args : {std::vector<std::string>{"--timeout", "-1"}, {"--timeout", "nan"},
                                          {"--timeout", "inf"}, {"--timeout", "x"}, {"--max-memory", "12"},
                                          {"--max-memory", "63M"}, {"--max-memory", "-1"}, {"--max-memory", "1T"},
                                          {"--max-memory", "G"}, {"--max-memory", "99999999999999999999G"}}) {
        std::vector<std::string> full = {"render", "-o", (dir / "o.png").string()};
        full.insert(full.end(), args.begin(), args.end());
        const CliRun r = run_facet(full);
        EXPECT_EQ(r.exit_code, 2) << args[0] << " " << args[1] << ": " << r.all();
        EXPECT_TRUE(contains(r.err, args[0])) << r.err;
        EXPECT_FALSE(fs::exists(dir / "o.png"));
    }
    // The accepted spellings render.
    for (const char* ok : {"0", "64", "512M", "65536K", "1G", "1g"}) {
        const CliRun r = run_facet({"render", "-o", (dir / "ok.png").string(), "--size", "16x16", "--max-memory", ok});
        EXPECT_EQ(r.exit_code, 0) << ok << ": " << r.all();
    }
}

}  // namespace
