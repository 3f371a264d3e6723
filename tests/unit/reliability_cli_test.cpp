// Hostile conditions at the command line (docs/RELIABILITY.md): a file that hangs is abandoned by
// `facet thumbs --timeout` while the batch finishes; resource limits from the command line are
// enforced; a write that fails (full disk, device that refuses data) leaves no output file and no
// temporary behind.
#include <gtest/gtest.h>

#include <sys/mount.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "facet/io.hpp"
#include "support/cli.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using facet_test::k_box_obj;
using facet_test::ScopedEnv;
using facet_test::CliRun;
using facet_test::run_facet;
using facet_test::write_text;

// Every file name under `dir` (recursively), relative to it.
std::vector<std::string> files_in(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir)) names.push_back(fs::relative(e.path(), dir).string());
    std::sort(names.begin(), names.end());
    return names;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// ---- facet thumbs --timeout ----------------------------------------------------------------------

TEST(ThumbsTimeout, AHangingFileIsAbandonedAndReportedWhileTheBatchFinishes) {
    const fs::path dir = facet_test::test_temp_dir("facet_reliability");
    write_text(dir / "in" / "a_good.obj", k_box_obj);
    write_text(dir / "in" / "b_hangs.obj", k_box_obj);
    write_text(dir / "in" / "c_good.obj", k_box_obj);
    // A temporary from an earlier abandoned run of the same file: cleared along with this run's.
    write_text(dir / "out" / "b_hangs.obj.png.tmp123456", "partial");

    const ScopedEnv hook("FACET_TEST_SLEEP_ON", "b_hangs");  // test hook: that file's worker sleeps
    const auto start = std::chrono::steady_clock::now();
    // One worker at a time: b_hangs is served by the worker that rendered a_good (the same folder),
    // with a timeout of its own.
    const CliRun r = run_facet({"thumbs", (dir / "in").string(), "-o", (dir / "out").string(), "--size", "32",
                                "--timeout", "1.5", "--threads", "1"});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(contains(r.err, "b_hangs.obj: gave up after 1.5 s")) << r.err;
    EXPECT_TRUE(contains(r.err, "2 rendered, 1 failed")) << r.err;
    EXPECT_EQ(files_in(dir / "out"), (std::vector<std::string>{"a_good.obj.png", "c_good.obj.png"}));
    EXPECT_TRUE(facet_test::decode_png(dir / "out" / "a_good.obj.png").ok());
    EXPECT_LT(seconds, 30.0) << "the hanging file held up the batch";
}

TEST(ThumbsTimeout, EveryWorkerHangingStillEndsWithEveryFileReported) {
    const fs::path dir = facet_test::test_temp_dir("facet_reliability");
    for (const char* name : {"x1.obj", "x2.obj", "x3.obj"}) write_text(dir / "in" / name, k_box_obj);
    const ScopedEnv hook("FACET_TEST_SLEEP_ON", "x");
    const CliRun r = run_facet({"thumbs", (dir / "in").string(), "-o", (dir / "out").string(), "--size", "16",
                                "--timeout", "0.5", "--threads", "2"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    for (const char* name : {"x1.obj", "x2.obj", "x3.obj"})
        EXPECT_TRUE(contains(r.err, std::string(name) + ": gave up after 0.5 s")) << r.err;
    EXPECT_TRUE(contains(r.err, "0 rendered, 3 failed")) << r.err;
    EXPECT_TRUE(files_in(dir / "out").empty());
}

// A file that crashes assimp (8 bytes found by fuzz/load_model_fuzzer: Debian's assimp 5.2.5
// dereferences a null string in its LightWave scene reader) costs only its own worker process:
// the batch goes on and reports it. (`facet render`: render_isolation_test.cpp.)
TEST(ThumbsIsolation, AFileThatCrashesTheReaderFailsAloneAndTheBatchFinishes) {
    const fs::path dir = facet_test::test_temp_dir("facet_reliability");
    write_text(dir / "in" / "a_good.obj", k_box_obj);
    write_text(dir / "in" / "b_crash.lws", std::string("\0\1\0\0\0\0\x1e}", 8));
    write_text(dir / "in" / "c_good.obj", k_box_obj);
    const CliRun r = run_facet({"thumbs", (dir / "in").string(), "-o", (dir / "out").string(), "--size", "24", "--threads", "2"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(contains(r.err, "2 rendered, 1 failed")) << r.err;
    EXPECT_TRUE(contains(r.err, "failed: " + (dir / "in" / "b_crash.lws").string() + ": ")) << r.err;
    // With Debian's assimp the reader crashes (a signal; under a sanitizer its report's exit
    // status); an assimp that reads the file cleanly gives an ordinary error instead.
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
    EXPECT_TRUE(contains(r.err, "b_crash.lws: the importer crashed (SIGSEGV")) << r.err;
#endif
    EXPECT_EQ(files_in(dir / "out"), (std::vector<std::string>{"a_good.obj.png", "c_good.obj.png"}));
}

// A worker serves the objects of one folder one after another (thumbs_command.cpp): a crash in the
// middle costs that object alone (run again in a fresh worker, where it crashes again, and reported
// once), the objects after it are rendered by fresh workers, a file that assimp reads (a PLY with
// colours) is given to a fresh worker too, and every image is the same bytes as the object rendered
// alone. (A hang in the middle: ThumbsTimeout above.)
TEST(ThumbsIsolation, AWorkerServingAFolderLosesOnlyTheObjectThatCrashes) {
    const fs::path dir = facet_test::test_temp_dir("facet_reliability");
    auto tetrahedron = [](int n) {
        return "v 0 0 0\nv " + std::to_string(0.5 + 0.1 * n) + " 0 0\nv 0 0.4 0\nv 0.1 0.2 " + std::to_string(1 + 0.2 * n) +
               "\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    };
    const std::vector<std::string> names{"a.obj", "b_crash.obj", "c.obj", "d.obj", "e.off"};
    for (std::size_t i = 0; i + 1 < names.size(); ++i) write_text(dir / "in" / names[i], tetrahedron(static_cast<int>(i)));
    write_text(dir / "in" / "e.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n");
    const ScopedEnv crash("FACET_TEST_CRASH_ON", "b_crash");
    write_text(dir / "in" / "f_colours.ply",
               "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
               "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 4\n"
               "property list uchar int vertex_indices\nend_header\n0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n"
               "0 0 1 255 255 0\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n");
    const CliRun r = run_facet({"thumbs", (dir / "in").string(), "-o", (dir / "out").string(), "--size", "24",
                                "--threads", "1", "--log", (dir / "log.jsonl").string()});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(contains(r.err, "5 rendered, 1 failed")) << r.err;
    EXPECT_TRUE(contains(r.err, "b_crash.obj: the importer crashed (SIGABRT")) << r.err;
    EXPECT_EQ(files_in(dir / "out"),
              (std::vector<std::string>{"a.obj.png", "c.obj.png", "d.obj.png", "e.off.png", "f_colours.ply.png"}));
    const std::string log = facet_test::read_file(dir / "log.jsonl");
    EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 6) << log;  // one line per object
    for (const std::string name : {"a.obj", "c.obj", "d.obj", "e.off", "f_colours.ply"}) {
        const CliRun alone = run_facet({"thumbs", (dir / "in" / name).string(), "-o", (dir / "alone").string(), "--size", "24"});
        ASSERT_EQ(alone.exit_code, 0) << alone.all();
        EXPECT_EQ(facet_test::read_file(dir / "out" / (name + ".png")), facet_test::read_file(dir / "alone" / (name + ".png")))
            << name;
    }
}

// The same across folders (a manifest's default, --worker-sharing batch): one object per folder, a
// crash in the middle costs only that object, and every image is the same bytes as with a worker
// per folder.
TEST(ThumbsIsolation, AWorkerServingABatchOfFoldersLosesOnlyTheObjectThatCrashes) {
    const fs::path dir = facet_test::test_temp_dir("facet_reliability");
    std::string manifest;
    for (const std::string name : {"a", "b_crash", "c", "d"}) {
        const std::size_t n = manifest.size();
        write_text(dir / name / "model.obj", "v 0 0 0\nv " + std::to_string(0.5 + 0.01 * static_cast<double>(n)) +
                                                 " 0 0\nv 0 0.4 0\nv 0.1 0.2 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
        manifest += "{\"id\": \"" + name + "\", \"path\": \"" + name + "/model.obj\"}\n";
    }
    write_text(dir / "objects.jsonl", manifest);
    const ScopedEnv crash("FACET_TEST_CRASH_ON", "b_crash");
    auto run = [&](const std::string& out, const std::string& sharing) {
        return run_facet({"thumbs", "--manifest", (dir / "objects.jsonl").string(), "-o", (dir / out).string(), "--size",
                          "24", "--threads", "1", "--worker-sharing", sharing});
    };
    const CliRun batch = run("batch", "batch");
    EXPECT_EQ(batch.exit_code, 1) << batch.all();
    EXPECT_TRUE(contains(batch.err, "3 rendered, 1 failed")) << batch.err;
    EXPECT_TRUE(contains(batch.err, "b_crash/model.obj: the importer crashed (SIGABRT")) << batch.err;
    EXPECT_EQ(files_in(dir / "batch"), (std::vector<std::string>{"a.png", "c.png", "d.png"}));
    const CliRun folder = run("folder", "folder");
    EXPECT_EQ(folder.exit_code, 1) << folder.all();
    for (const std::string name : {"a.png", "c.png", "d.png"})
        EXPECT_EQ(facet_test::read_file(dir / "batch" / name), facet_test::read_file(dir / "folder" / name)) << name;
}

// Without the variable the hook does nothing (the same names render).
TEST(ThumbsTimeout, TheTestHookIsInertWithoutItsVariable) {
    const fs::path dir = facet_test::test_temp_dir("facet_reliability");
    write_text(dir / "in" / "b_hangs.obj", k_box_obj);
    unsetenv("FACET_TEST_SLEEP_ON");
    const CliRun r = run_facet({"thumbs", (dir / "in").string(), "-o", (dir / "out").string(), "--size", "16", "--timeout", "30"});
    EXPECT_EQ(r.exit_code, 0) << r.all();
    EXPECT_TRUE(fs::exists(dir / "out" / "b_hangs.obj.png"));
}

TEST(ThumbsTimeout, InvalidTimeoutsAreUsageErrors) {
    const fs::path dir = facet_test::test_temp_dir("facet_reliability");
    write_text(dir / "a.obj", k_box_obj);
    for (const char* bad : {"-1", "abc", "nan", "inf"}) {
        const CliRun r = run_facet({"thumbs", (dir / "a.obj").string(), "-o", (dir / "out").string(), "--timeout", bad});
        EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.all();
        EXPECT_FALSE(fs::exists(dir / "out" / "a.obj.png")) << bad;
    }
}

// ---- resource limits on the command line ---------------------------------------------------------

TEST(CliLimits, MaxTrianglesRefusesLargerModels) {
    const fs::path dir = facet_test::test_temp_dir("facet_reliability");
    const std::string box = write_text(dir / "box.obj", k_box_obj);  // 12 triangles
    const CliRun over = run_facet({"render", box, "-o", (dir / "over.png").string(), "--size", "16x16", "--max-triangles", "11"});
    EXPECT_EQ(over.exit_code, 1) << over.all();
    EXPECT_TRUE(contains(over.err, "more than the limit of 11")) << over.err;
    EXPECT_FALSE(fs::exists(dir / "over.png"));
    const CliRun at = run_facet({"render", box, "-o", (dir / "at.png").string(), "--size", "16x16", "--max-triangles", "12"});
    EXPECT_EQ(at.exit_code, 0) << at.all();

    // Binary STL: refused from its header, before assimp reads it.
    std::string stl(84 + 50 * 3, '\0');
    stl[80] = 3;
    const std::string three = write_text(dir / "three.stl", stl);
    const CliRun s = run_facet({"render", three, "-o", (dir / "s.png").string(), "--max-triangles", "2"});
    EXPECT_EQ(s.exit_code, 1) << s.all();
    EXPECT_TRUE(contains(s.err, "has 3 triangles, more than the limit of 2")) << s.err;

    const CliRun thumbs = run_facet({"thumbs", box, "-o", (dir / "thumbs").string(), "--max-triangles", "5"});
    EXPECT_EQ(thumbs.exit_code, 1) << thumbs.all();
    EXPECT_TRUE(contains(thumbs.err, "more than the limit of 5")) << thumbs.err;
}

TEST(CliLimits, MaxTextureSizeLeavesOutLargerTexturesWithAWarning) {
    const fs::path dir = facet_test::test_temp_dir("facet_reliability");
    facet::Image tex{64, 32, std::vector<facet::Rgba8>(64 * 32, facet::Rgba8{255, 0, 0, 255})};
    ASSERT_TRUE(facet::write_png((dir / "red.png").string(), tex).ok());
    write_text(dir / "m.mtl", "newmtl red\nKd 1 1 1\nmap_Kd red.png\n");
    const std::string obj = write_text(dir / "quad.obj",
                                       "mtllib m.mtl\nusemtl red\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
    const CliRun small = run_facet({"render", obj, "-o", (dir / "small.png").string(), "--size", "16x16", "--shading",
                                    "texture", "--max-texture-size", "32"});
    EXPECT_EQ(small.exit_code, 0) << small.all();
    EXPECT_TRUE(contains(small.err, "warning:")) << small.err;
    EXPECT_TRUE(contains(small.err, "64x32, over the texture limits (32 per side")) << small.err;
    const auto without = facet_test::decode_png(dir / "small.png");
    ASSERT_TRUE(without.ok()) << without.error;
    EXPECT_EQ(without.at(8, 8), (facet::Rgba8{255, 255, 255, 255}));  // the material colour stands in

    const CliRun fits = run_facet({"render", obj, "-o", (dir / "fits.png").string(), "--size", "16x16", "--shading",
                                   "texture", "--max-texture-size", "64"});
    EXPECT_EQ(fits.exit_code, 0) << fits.all();
    EXPECT_FALSE(contains(fits.err, "warning:")) << fits.err;
    const auto with = facet_test::decode_png(dir / "fits.png");
    ASSERT_TRUE(with.ok()) << with.error;
    EXPECT_EQ(with.at(8, 8), (facet::Rgba8{255, 0, 0, 255}));
}

TEST(CliLimits, NonPositiveLimitsAreUsageErrors) {
    for (std::vector<std::string> args : {std::vector<std::string>{"--max-triangles", "0"}, {"--max-triangles", "-5"},
                                          {"--max-texture-size", "0"}, {"--max-texture-size", "-1"}}) {
        std::vector<std::string> full = {"render", "-o", "/dev/null"};
        full.insert(full.end(), args.begin(), args.end());
        EXPECT_EQ(run_facet(full).exit_code, 2) << args[0] << " " << args[1];
    }
}

// ---- failed writes leave nothing behind ----------------------------------------------------------

TEST(AtomicOutput, ADeviceThatRefusesTheDataIsAnErrorAndNoFileAppears) {
    const CliRun r = run_facet({"render", "-o", "/dev/full", "--size", "32x32"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(contains(r.err, "/dev/full")) << r.err;
    EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

TEST(AtomicOutput, AnOutputPathThroughAFileFailsWithoutLeavingAnything) {
    const fs::path dir = facet_test::test_temp_dir("facet_reliability");
    write_text(dir / "file", "not a directory");
    const CliRun r = run_facet({"render", "-o", (dir / "file" / "out.png").string(), "--size", "16x16"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_EQ(files_in(dir), (std::vector<std::string>{"file"}));
}

// A full disk: a 64 KiB tmpfs filled up to the last byte (mounting needs root; skipped otherwise).
// Files can still be created on it, so each write gets as far as creating its temporary and
// fails writing the data.
class FullDisk : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = facet_test::test_temp_dir("facet_reliability") / "small";
        fs::create_directories(dir_);
        if (mount("tmpfs", dir_.c_str(), "tmpfs", 0, "size=64k") != 0)
            GTEST_SKIP() << "cannot mount a small tmpfs to fill (needs root): " << std::strerror(errno);
        mounted_ = true;
        std::FILE* f = std::fopen((dir_ / "filler").c_str(), "wb");
        ASSERT_NE(f, nullptr);
        std::setvbuf(f, nullptr, _IONBF, 0);
        const char byte = 'x';
        std::size_t written = 0;  // byte by byte, unbuffered: every last byte gets used
        while (std::fwrite(&byte, 1, 1, f) == 1 && ++written < (1u << 20)) {}
        std::fclose(f);
        ASSERT_LT(written, 1u << 20) << "the tmpfs did not fill up";
    }
    void TearDown() override {
        if (mounted_) umount2(dir_.c_str(), MNT_DETACH);
    }
    // Makes room again: the same file system then takes the same output.
    void empty_disk() { fs::remove(dir_ / "filler"); }
    std::vector<std::string> left_behind() {
        std::vector<std::string> names = files_in(dir_);
        names.erase(std::remove(names.begin(), names.end(), "filler"), names.end());
        return names;
    }
    fs::path dir_;
    bool mounted_ = false;
};

TEST_F(FullDisk, RenderLeavesNoFileAndNoTemporary) {
    const std::vector<std::string> args = {"render", "-o", (dir_ / "out.png").string(), "--size", "64x48"};
    const CliRun r = run_facet(args);
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(contains(r.err, "out.png")) << r.err;
    EXPECT_TRUE(left_behind().empty()) << "left behind: " << testing::PrintToString(left_behind());
    empty_disk();
    const CliRun again = run_facet(args);
    EXPECT_EQ(again.exit_code, 0) << again.all();
    EXPECT_EQ(left_behind(), (std::vector<std::string>{"out.png"}));
}

// The colour image fits, the depth image does not: the colour image is taken back too.
TEST_F(FullDisk, DepthOutputThatDoesNotFitTakesTheColourImageBackToo) {
    const fs::path elsewhere = dir_.parent_path() / "colour.png";
    const CliRun r = run_facet({"render", "-o", elsewhere.string(), "--depth-out", (dir_ / "depth.png").string(), "--size",
                                "64x48"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(contains(r.err, "depth.png")) << r.err;
    EXPECT_FALSE(fs::exists(elsewhere));
    EXPECT_TRUE(left_behind().empty()) << "left behind: " << testing::PrintToString(left_behind());
}

TEST_F(FullDisk, ThumbsThatDoNotFitFailAndLeaveNoTemporaries) {
    const fs::path in = dir_.parent_path() / "in";
    write_text(in / "a.obj", k_box_obj);
    write_text(in / "b.obj", k_box_obj);
    const CliRun r = run_facet({"thumbs", in.string(), "-o", dir_.string(), "--size", "64"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(contains(r.err, "0 rendered, 2 failed")) << r.err;
    EXPECT_TRUE(left_behind().empty()) << "left behind: " << testing::PrintToString(left_behind());
    empty_disk();
    const CliRun again = run_facet({"thumbs", in.string(), "-o", dir_.string(), "--size", "64"});
    EXPECT_EQ(again.exit_code, 0) << again.all();
    EXPECT_EQ(left_behind(), (std::vector<std::string>{"a.obj.png", "b.obj.png"}));
}

}  // namespace
