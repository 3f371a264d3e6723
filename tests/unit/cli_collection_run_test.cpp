// `facet thumbs` over collections as a script sees it: a manifest's objects rendered under their
// ids' names and options, shards that together render a fixed manifest exactly once, bad entries
// reported one by one while the batch goes on, the results log, --resume, and a run killed with
// SIGKILL at random moments (a fixed seed) and resumed until done: every object then has exactly
// one "ok" line, its outputs are the same bytes as an uninterrupted run's, and no temporary file
// or torn log line is left. The log is read with apps/cli/json (tested on its own in
// cli_collection_test.cpp).
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "json.hpp"
#include "support/cli.hpp"
#include "support/test_data.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using facet::cli::json::Value;
using facet_test::CliRun;
using facet_test::decode_png;
using facet_test::run_facet;
using facet_test::write_text;

fs::path temp_dir() { return facet_test::test_temp_dir("facet_collection_run"); }

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : name_(name) { setenv(name, value, 1); }
    ~ScopedEnv() { unsetenv(name_); }

private:
    const char* name_;
};

// A small model that differs with `n` (a lopsided tetrahedron, taller along +Z than +Y, so that
// --up-axis z changes the picture).
std::string model_obj(int n) {
    std::ostringstream s;
    const double a = 0.5 + 0.07 * (n % 11), b = 0.3 + 0.05 * (n % 7);
    s << "v 0 0 0\nv " << a << " 0 0\nv 0 " << b << " 0\nv 0.1 0.2 " << 1.5 + 0.1 * (n % 5) << "\n";
    s << "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    return s.str();
}

// Every file under `dir`, relative to it.
std::set<std::string> files_in(const fs::path& dir) {
    std::set<std::string> names;
    if (!fs::exists(dir)) return names;
    for (const auto& e : fs::recursive_directory_iterator(dir)) names.insert(fs::relative(e.path(), dir).string());
    return names;
}

struct LogLine {
    std::string id, status, reason, error, hash;
    std::vector<std::string> outputs;
};

// Every line of a log; a line that is not a complete JSON object with the documented keys fails
// the test.
std::vector<LogLine> read_log(const fs::path& path) {
    std::vector<LogLine> lines;
    const std::string text = facet_test::read_file(path);
    EXPECT_TRUE(text.empty() || text.back() == '\n') << "the log ends in a torn line";
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        const facet::Result<Value> v = facet::cli::json::parse(line);
        EXPECT_TRUE(v.ok()) << "not JSON: " << line;
        if (!v.ok()) continue;
        for (const char* key : {"id", "path", "line", "status", "reason", "error", "triangles", "load_ms", "render_ms",
                                "write_ms", "total_ms", "outputs", "options_hash"})
            EXPECT_NE(v->find(key), nullptr) << key << " missing: " << line;
        LogLine l;
        const auto text_of = [&](const char* key) {
            const Value* x = v->find(key);
            return x && x->is(Value::Type::string) ? x->text : std::string();
        };
        l.id = text_of("id");
        l.status = text_of("status");
        l.reason = text_of("reason");
        l.error = text_of("error");
        l.hash = text_of("options_hash");
        if (const Value* o = v->find("outputs"))
            for (const Value& x : o->items) l.outputs.push_back(x.text);
        if (l.status == "ok") {
            EXPECT_TRUE(v->find("triangles")->is(Value::Type::number)) << line;
            EXPECT_TRUE(v->find("render_ms")->is(Value::Type::number)) << line;
            EXPECT_TRUE(v->find("error")->is(Value::Type::null)) << line;
        }
        lines.push_back(l);
    }
    return lines;
}

std::map<std::string, int> ok_count_by_id(const std::vector<LogLine>& log) {
    std::map<std::string, int> n;
    for (const LogLine& l : log)
        if (l.status == "ok") ++n[l.id];
    return n;
}

TEST(CliCollection, ManifestOutputsAreNamedByIdInsideTheFolderWithPerObjectOptions) {
    const fs::path dir = temp_dir();
    write_text(dir / "models" / "a.obj", model_obj(1));
    write_text(dir / "models" / "b.obj", model_obj(2));
    write_text(dir / "m.jsonl",
               "{\"id\": \"plain\", \"path\": \"models/a.obj\"}\n"
               "{\"id\": \"../../escape\", \"path\": \"models/b.obj\"}\n"
               "{\"id\": \"/etc/x\", \"path\": \"models/b.obj\", \"size\": \"40x24\"}\n"
               "{\"id\": \"zup\", \"path\": \"models/a.obj\", \"up_axis\": \"z\", \"size\": 36}\n"
               "{\"path\": \"models/b.obj\"}\n");
    const fs::path out = dir / "deep" / "out";
    const CliRun r = run_facet({"thumbs", "--manifest", (dir / "m.jsonl").string(), "-o", out.string(), "--size", "32"});
    ASSERT_EQ(r.exit_code, 0) << r.all();
    EXPECT_EQ(files_in(out), (std::set<std::string>{"plain.png", "%2E.%2F..%2Fescape.png", "%2Fetc%2Fx.png", "zup.png",
                                                     "models%2Fb.obj.png"}));
    EXPECT_EQ(files_in(dir / "deep"), (std::set<std::string>{"out", "out/plain.png", "out/%2E.%2F..%2Fescape.png",
                                                              "out/%2Fetc%2Fx.png", "out/zup.png", "out/models%2Fb.obj.png"}));
    EXPECT_FALSE(fs::exists(dir / "escape.png"));
    EXPECT_EQ(decode_png(out / "plain.png").width, 32u);
    EXPECT_EQ(decode_png(out / "%2Fetc%2Fx.png").width, 40u);
    EXPECT_EQ(decode_png(out / "%2Fetc%2Fx.png").height, 24u);
    EXPECT_EQ(decode_png(out / "zup.png").width, 36u);

    // The same pixels as `facet render` of the file with the thumbnail defaults (--aa 2, --contact-shadow
    // 0.6 among them) and the entry's options.
    const fs::path single = dir / "single.png";
    ASSERT_EQ(run_facet({"render", (dir / "models" / "a.obj").string(), "--size", "36x36", "--azimuth", "35", "--elevation",
                         "25", "--up-axis", "z", "--aa", "2", "--contact-shadow", "0.6", "-o", single.string()})
                  .exit_code,
              0);
    EXPECT_TRUE(decode_png(single).rgba == decode_png(out / "zup.png").rgba);
    ASSERT_EQ(run_facet({"render", (dir / "models" / "a.obj").string(), "--size", "36x36", "--azimuth", "35", "--elevation",
                         "25", "--aa", "2", "--contact-shadow", "0.6", "-o", single.string()})
                  .exit_code,
              0);
    EXPECT_FALSE(decode_png(single).rgba == decode_png(out / "zup.png").rgba) << "up_axis had no effect";
}

TEST(CliCollection, TextManifestPathsAreRelativeToTheManifestAndAreTheIds) {
    const fs::path dir = temp_dir();
    write_text(dir / "set" / "x" / "a.obj", model_obj(3));
    write_text(dir / "set" / "b.stl",
               "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n");
    write_text(dir / "set" / "list.txt", "# two models\nx/a.obj\n\nb.stl\n");
    const fs::path out = dir / "out";
    // The test's working directory is not the manifest's: the paths resolve against the manifest.
    const CliRun r = run_facet({"thumbs", "--manifest", (dir / "set" / "list.txt").string(), "-o", out.string(), "--size", "24"});
    ASSERT_EQ(r.exit_code, 0) << r.all();
    EXPECT_EQ(files_in(out), (std::set<std::string>{"x%2Fa.obj.png", "b.stl.png"}));
}

TEST(CliCollection, ThreeShardsRenderAFixedManifestExactlyOnceAlwaysTheSameWay) {
    const fs::path dir = temp_dir();
    write_text(dir / "m.obj", model_obj(4));
    std::string manifest;
    std::set<std::string> all;
    for (int i = 0; i < 12; ++i) {
        const std::string id = std::string("chair-") + (i < 10 ? "0" : "") + std::to_string(i);
        manifest += "{\"id\": \"" + id + "\", \"path\": \"m.obj\"}\n";
        all.insert(id + ".png");
    }
    write_text(dir / "m.jsonl", manifest);
    // The split the documented hash gives (computed apart from facet; also cli_collection_test).
    const std::map<int, std::set<std::string>> expected = {
        {0, {"chair-06.png"}},
        {1, {"chair-03.png", "chair-04.png", "chair-05.png", "chair-07.png", "chair-08.png", "chair-11.png"}},
        {2, {"chair-00.png", "chair-01.png", "chair-02.png", "chair-09.png", "chair-10.png"}},
    };
    std::set<std::string> seen;
    for (int k = 0; k < 3; ++k) {
        const fs::path out = dir / ("shard" + std::to_string(k));
        const fs::path log = dir / ("log" + std::to_string(k) + ".jsonl");
        const CliRun r = run_facet({"thumbs", "--manifest", (dir / "m.jsonl").string(), "-o", out.string(), "--size", "16",
                                    "--shard", std::to_string(k) + "/3", "--log", log.string()});
        ASSERT_EQ(r.exit_code, 0) << r.all();
        EXPECT_EQ(files_in(out), expected.at(k)) << k;
        for (const std::string& f : files_in(out)) EXPECT_TRUE(seen.insert(f).second) << f << " rendered by two shards";
        EXPECT_EQ(read_log(log).size(), expected.at(k).size());
    }
    EXPECT_EQ(seen, all);
    // Again, with other thread counts: the same split.
    const CliRun again = run_facet({"thumbs", "--manifest", (dir / "m.jsonl").string(), "-o", (dir / "again").string(),
                                    "--size", "16", "--shard", "1/3", "--threads", "1"});
    ASSERT_EQ(again.exit_code, 0) << again.all();
    EXPECT_EQ(files_in(dir / "again"), expected.at(1));
}

TEST(CliCollection, BadEntriesAreReportedOneByOneAndTheBatchGoesOn) {
    const fs::path dir = temp_dir();
    write_text(dir / "good.obj", model_obj(5));
    write_text(dir / "broken.obj", std::string(300, '\x07'));
    fs::create_directories(dir / "folder.obj");
    write_text(dir / "m.jsonl",
               "{\"id\": \"good\", \"path\": \"good.obj\"}\n"
               "{\"id\": \"missing\", \"path\": \"nowhere.obj\"}\n"
               "{\"id\": \"folder\", \"path\": \"folder.obj\"}\n"
               "{\"id\": \"broken\", \"path\": \"broken.obj\"}\n"
               "{\"id\": \"good\", \"path\": \"good.obj\", \"size\": 20}\n"
               "{\"id\": \"size\", \"path\": \"good.obj\", \"size\": \"0x4\"}\n"
               "{\"id\": \"axis\", \"path\": \"good.obj\", \"up_axis\": \"x\"}\n"
               "{\"id\": \"key\", \"path\": \"good.obj\", \"azimuth\": 3}\n"
               "{\"id\": \"json\", \"path\": \"good.obj\"\n"
               "{\"id\": \"views\", \"path\": \"good.obj\", \"views\": \"orbit:0\"}\n"
               "{\"id\": \"passes\", \"path\": \"good.obj\", \"passes\": [\"color\", \"colour\"]}\n"
               "{\"id\": \"good2\", \"path\": \"good.obj\", \"size\": 20}\n");
    const fs::path log = dir / "log.jsonl";
    const CliRun r = run_facet({"thumbs", "--manifest", (dir / "m.jsonl").string(), "-o", (dir / "out").string(), "--size",
                                "24", "--log", log.string()});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_EQ(files_in(dir / "out"), (std::set<std::string>{"good.png", "good2.png"}));
    std::map<std::string, std::string> reason;  // by manifest line
    for (const LogLine& l : read_log(log)) reason[l.status == "ok" ? l.id : l.error.substr(0, l.error.find(": "))] = l.reason;
    const std::string m = (dir / "m.jsonl").string();
    EXPECT_EQ(reason, (std::map<std::string, std::string>{{"good", ""},
                                                          {(dir / "nowhere.obj").string(), "missing"},
                                                          {(dir / "folder.obj").string(), "unreadable"},
                                                          {(dir / "broken.obj").string(), "bad_file"},
                                                          {m + ":5", "duplicate_id"},
                                                          {m + ":6", "bad_entry"},
                                                          {m + ":7", "bad_entry"},
                                                          {m + ":8", "bad_entry"},
                                                          {m + ":9", "bad_entry"},
                                                          {m + ":10", "bad_entry"},
                                                          {m + ":11", "bad_entry"},
                                                          {"good2", ""}}))
        << facet_test::read_file(log);
    // The summary groups them by reason, each with its line.
    EXPECT_TRUE(contains(r.err, "2 rendered, 10 failed")) << r.err;
    for (const char* group : {"\n  missing file: 1\n", "\n  unreadable file: 1\n", "\n  not a valid model: 1\n",
                              "\n  duplicate id: 1\n", "\n  bad manifest entry: 6\n"})
        EXPECT_TRUE(contains(r.err, group)) << group << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, "    failed: " + m + ":8: unknown key \"azimuth\"")) << r.err;
    EXPECT_TRUE(contains(r.err, "    failed: " + m + ":6: size must be N or WxH, each at least 1, got '0x4'")) << r.err;
    EXPECT_TRUE(contains(r.err, "    failed: " + m + ":10: views: ")) << r.err;
    EXPECT_TRUE(contains(r.err, "    failed: " + m + ":11: passes: unknown pass 'colour'")) << r.err;
}

// Entries with views or passes: a folder per object with what `facet render --views --passes`
// writes, the same bytes, every file in the log line; resumed, redone and replaced as a whole.
TEST(CliCollection, ViewsAndPassesWriteAFolderPerObject) {
    const fs::path dir = temp_dir();
    write_text(dir / "a.obj", model_obj(4));
    const std::vector<std::string> thumb_defaults{"--azimuth", "35", "--elevation", "25", "--aa", "2", "--contact-shadow", "0.6"};
    auto render = [&](const fs::path& out, std::vector<std::string> args) {
        args.insert(args.begin(), {"render", (dir / "a.obj").string(), "-o", out.string()});
        args.insert(args.end(), thumb_defaults.begin(), thumb_defaults.end());
        const CliRun r = run_facet(args);
        EXPECT_EQ(r.exit_code, 0) << r.all();
    };
    render(dir / "cams", {"--views", "orbit:2:40", "--size", "28x20"});  // a cameras file for "file:"
    const auto write_manifest = [&](const std::string& vp_views) {
        write_text(dir / "m.jsonl",
                   "{\"id\": \"plain\", \"path\": \"a.obj\"}\n"
                   "{\"id\": \"p\", \"path\": \"a.obj\", \"passes\": [\"color\", \"depth\"]}\n"
                   "{\"id\": \"v\", \"path\": \"a.obj\", \"views\": \"orbit:3\", \"size\": 20}\n"
                   "{\"id\": \"v/p\", \"path\": \"a.obj\", \"views\": \"" + vp_views +
                       "\", \"passes\": \"color,normal,instance\"}\n"
                   "{\"id\": \"cams\", \"path\": \"a.obj\", \"views\": \"file:cams/cameras.json\"}\n");
    };
    write_manifest("orbit:2");
    const fs::path out = dir / "out", log = dir / "log.jsonl";
    auto thumbs = [&] {
        return run_facet({"thumbs", "--manifest", (dir / "m.jsonl").string(), "-o", out.string(), "--size", "24", "--log",
                          log.string(), "--resume"});
    };
    const CliRun first = thumbs();
    ASSERT_EQ(first.exit_code, 0) << first.all();
    const std::set<std::string> folders{"p", "p/color", "p/depth", "v", "v/color", "v%2Fp", "v%2Fp/color", "v%2Fp/normal",
                                        "v%2Fp/instance", "cams", "cams/color"};
    std::set<std::string> files{"plain.png",
                                "p/cameras.json", "p/transforms.json", "p/color/0000.png", "p/depth/0000.npy",
                                "v/cameras.json", "v/transforms.json", "v/color/0000.png", "v/color/0001.png", "v/color/0002.png",
                                "v%2Fp/cameras.json", "v%2Fp/transforms.json", "v%2Fp/color/0000.png", "v%2Fp/color/0001.png",
                                "v%2Fp/normal/0000.npy", "v%2Fp/normal/0001.npy", "v%2Fp/instance/0000.png",
                                "v%2Fp/instance/0001.png",
                                "cams/cameras.json", "cams/transforms.json", "cams/color/0000.png", "cams/color/0001.png"};
    std::set<std::string> all = files;
    all.insert(folders.begin(), folders.end());
    EXPECT_EQ(files_in(out), all);
    // Each line lists its object's files, sorted.
    std::set<std::string> logged;
    for (const LogLine& l : read_log(log)) {
        EXPECT_EQ(l.status, "ok") << l.id << ": " << l.error;
        EXPECT_TRUE(std::is_sorted(l.outputs.begin(), l.outputs.end())) << l.id;
        logged.insert(l.outputs.begin(), l.outputs.end());
    }
    EXPECT_EQ(logged, files);

    // The same bytes as facet render with thumbs' defaults (--aa 2, the contact shadow): the rig with the
    // entry's size, and the cameras file at its own size.
    render(dir / "ref_v", {"--views", "orbit:3", "--size", "20x20"});
    render(dir / "ref_vp", {"--views", "orbit:2", "--passes", "color,normal,instance", "--size", "24x24"});
    for (const auto& [folder, ref] : {std::pair{"v", "ref_v"}, {"v%2Fp", "ref_vp"}, {"cams", "cams"}}) {
        for (const std::string& f : files_in(dir / ref)) {
            if (fs::is_regular_file(dir / ref / f)) {
                EXPECT_EQ(facet_test::read_file(out / folder / f), facet_test::read_file(dir / ref / f)) << folder << "/" << f;
            }
        }
    }
    EXPECT_EQ(decode_png(out / "cams" / "color" / "0001.png").width, 28u);

    // Resumed: nothing to do; a file gone or a staging folder a killed run left: that object alone.
    const CliRun again = thumbs();
    EXPECT_TRUE(contains(again.err, "0 rendered, 0 failed, 5 skipped")) << again.err;
    fs::remove(out / "v%2Fp" / "normal" / "0001.npy");
    write_text(out / "v.tmp4242" / "color" / "0000.png", "partial");
    const CliRun redo = thumbs();
    EXPECT_TRUE(contains(redo.err, "1 rendered, 0 failed, 4 skipped")) << redo.err;
    EXPECT_EQ(files_in(out), all);
    EXPECT_EQ(read_log(log).back().id, "v/p");

    // Another rig: the object's folder is replaced, not merged (no view 0001 left of the old one).
    write_manifest("orbit:1");
    const CliRun one = thumbs();
    EXPECT_TRUE(contains(one.err, "1 rendered, 0 failed, 4 skipped")) << one.err;
    for (const char* gone : {"v%2Fp/color/0001.png", "v%2Fp/normal/0001.npy", "v%2Fp/instance/0001.png"}) {
        files.erase(gone);
        all.erase(gone);
    }
    EXPECT_EQ(files_in(out), all);
    EXPECT_EQ(read_log(log).back().outputs.size(), 5u);
}

TEST(CliCollection, ResumeSkipsWhatIsDoneWithTheSameOptionsAndRedoesTheRest) {
    const fs::path dir = temp_dir();
    std::string manifest;
    for (int i = 0; i < 6; ++i) {
        write_text(dir / ("m" + std::to_string(i) + ".obj"), model_obj(i));
        manifest += "m" + std::to_string(i) + ".obj\n";
    }
    write_text(dir / "list.txt", manifest);
    const fs::path out = dir / "out", log = dir / "log.jsonl";
    auto run = [&](std::vector<std::string> extra) {
        std::vector<std::string> args{"thumbs", "--manifest", (dir / "list.txt").string(), "-o", out.string(), "--log",
                                      log.string(), "--resume"};
        if (std::find(extra.begin(), extra.end(), "--size") == extra.end()) extra.insert(extra.end(), {"--size", "24"});
        args.insert(args.end(), extra.begin(), extra.end());
        return run_facet(args);
    };
    const CliRun first = run({});  // a missing log: nothing done before
    ASSERT_EQ(first.exit_code, 0) << first.all();
    EXPECT_TRUE(contains(first.err, "6 rendered, 0 failed")) << first.err;
    const std::vector<LogLine> first_log = read_log(log);
    ASSERT_EQ(first_log.size(), 6u);
    const std::string hash = first_log[0].hash;
    EXPECT_EQ(hash.size(), 16u);
    for (const LogLine& l : first_log) EXPECT_EQ(l.hash, hash);

    // Other threads, ISA, timeout and memory cap: the same bytes, so nothing to redo.
    const CliRun same = run({"--threads", "2", "--isa", "scalar", "--timeout", "30", "--max-memory", "1G"});
    ASSERT_EQ(same.exit_code, 0) << same.all();
    EXPECT_TRUE(contains(same.err, "0 rendered, 0 failed, 6 skipped (done before)")) << same.err;
    EXPECT_EQ(read_log(log).size(), 6u) << "skipped objects add no line";

    // A removed output, and a damaged empty one: those two are redone.
    fs::remove(out / "m2.obj.png");
    write_text(out / "m4.obj.png", "");
    const CliRun two = run({});
    ASSERT_EQ(two.exit_code, 0) << two.all();
    EXPECT_TRUE(contains(two.err, "2 rendered, 0 failed, 4 skipped")) << two.err;
    EXPECT_TRUE(decode_png(out / "m4.obj.png").ok());

    // Other options that change the image: everything is redone, under another hash.
    for (const std::vector<std::string>& changed : {std::vector<std::string>{"--size", "28"}, {"--shading", "flat"},
                                                     {"--background", "1,0,0"}, {"--azimuth", "10"}}) {
        const CliRun redo = run(changed);
        ASSERT_EQ(redo.exit_code, 0) << redo.all();
        EXPECT_TRUE(contains(redo.err, "6 rendered, 0 failed")) << changed[0] << ": " << redo.err;
        EXPECT_NE(read_log(log).back().hash, hash) << changed[0];
    }
    // And back to the first options: redone again, since the outputs are now another run's.
    const CliRun back = run({});
    EXPECT_TRUE(contains(back.err, "6 rendered, 0 failed")) << back.err;
    EXPECT_EQ(read_log(log).back().hash, hash);
    EXPECT_EQ(decode_png(out / "m0.obj.png").width, 24u);
}

TEST(CliCollection, AnObjectRedoneWithOtherOptionsLosesItsOldOutputFirst) {
    const fs::path dir = temp_dir();
    write_text(dir / "keep.obj", model_obj(1));
    write_text(dir / "stuck.obj", model_obj(2));
    write_text(dir / "list.txt", "keep.obj\nstuck.obj\n");
    const fs::path out = dir / "out", log = dir / "log.jsonl";
    const std::vector<std::string> base{"thumbs", "--manifest", (dir / "list.txt").string(), "-o", out.string(),
                                        "--log",  log.string(), "--resume", "--timeout", "1"};
    auto run = [&](const char* size) {
        std::vector<std::string> args = base;
        args.insert(args.end(), {"--size", size});
        return run_facet(args);
    };
    ASSERT_EQ(run("24").exit_code, 0);
    {
        // With other options stuck.obj hangs and is abandoned: its 24-pixel image must not stay,
        // or a resume with the first options would keep it although the log's last word on it
        // is a failure with others.
        const ScopedEnv hook("FACET_TEST_SLEEP_ON", "stuck");
        const CliRun r = run("20");
        EXPECT_EQ(r.exit_code, 1) << r.all();
        EXPECT_TRUE(contains(r.err, "1 rendered, 1 failed")) << r.err;
    }
    EXPECT_FALSE(fs::exists(out / "stuck.obj.png"));
    EXPECT_EQ(decode_png(out / "keep.obj.png").width, 20u);
    const CliRun r = run("24");
    ASSERT_EQ(r.exit_code, 0) << r.all();
    EXPECT_TRUE(contains(r.err, "2 rendered, 0 failed")) << r.err;
    EXPECT_EQ(decode_png(out / "stuck.obj.png").width, 24u);
}

TEST(CliCollection, ATornLogLineIsCutAndItsObjectRedone) {
    const fs::path dir = temp_dir();
    write_text(dir / "a.obj", model_obj(1));
    write_text(dir / "b.obj", model_obj(2));
    write_text(dir / "list.txt", "a.obj\nb.obj\n");
    const fs::path out = dir / "out", log = dir / "log.jsonl";
    const std::vector<std::string> args{"thumbs", "--manifest", (dir / "list.txt").string(), "-o", out.string(),
                                        "--log",  log.string(),  "--resume", "--size", "16"};
    ASSERT_EQ(run_facet(args).exit_code, 0);
    // As if the run had been killed in the middle of b's line.
    std::string text = facet_test::read_file(log);
    const std::size_t b_line = text.find("{\"id\":\"b.obj\"");
    ASSERT_NE(b_line, std::string::npos);
    const std::string a_text = b_line == 0 ? text.substr(text.find('\n') + 1) : text.substr(0, b_line);
    const std::string b_text = b_line == 0 ? text.substr(0, text.find('\n') + 1) : text.substr(b_line);
    facet_test::write_file(log, a_text + b_text.substr(0, b_text.size() / 2));
    const CliRun r = run_facet(args);
    ASSERT_EQ(r.exit_code, 0) << r.all();
    EXPECT_TRUE(contains(r.err, "1 rendered, 0 failed, 1 skipped")) << r.err;
    const std::vector<LogLine> lines = read_log(log);  // every line whole
    EXPECT_EQ(ok_count_by_id(lines), (std::map<std::string, int>{{"a.obj", 1}, {"b.obj", 1}}));
}

// Starts facet with `args` (stdout and stderr to /dev/null) and returns its process id.
pid_t spawn_facet(const std::vector<std::string>& args) {
    const std::string binary = facet_test::facet_binary().string();
    std::vector<char*> argv{const_cast<char*>(binary.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawnattr_t attributes;  // a process group of its own, which its workers join
    posix_spawnattr_init(&attributes);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
    pid_t pid = -1;
    const int spawned = posix_spawn(&pid, binary.c_str(), &actions, &attributes, argv.data(), environ);
    posix_spawnattr_destroy(&attributes);
    posix_spawn_file_actions_destroy(&actions);
    return spawned == 0 ? pid : -1;
}

TEST(CliCollection, KilledAtRandomMomentsThenResumedRendersEveryObjectOnceWithNoDamage) {
    const fs::path dir = temp_dir();
    constexpr int k_objects = 40;
    std::string manifest;
    // Each model in a folder of its own, so that each has a worker of its own (a worker serves the
    // objects of one folder in turn, ~1 ms each here): runs slow enough to be killed in the middle.
    for (int i = 0; i < k_objects; ++i) {
        write_text(dir / "models" / ("m" + std::to_string(i)) / "m.obj", model_obj(i));
        manifest += "{\"id\": \"obj-" + std::to_string(i) + "\", \"path\": \"models/m" + std::to_string(i) + "/m.obj\"" +
                    (i % 3 == 0 ? ", \"size\": 20" : "") + "}\n";
    }
    write_text(dir / "m.jsonl", manifest);
    const fs::path out = dir / "out", log = dir / "log.jsonl", ref = dir / "ref";

    // The uninterrupted run the result must equal.
    const CliRun reference = run_facet({"thumbs", "--manifest", (dir / "m.jsonl").string(), "-o", ref.string(), "--size",
                                        "24", "--threads", "2"});
    ASSERT_EQ(reference.exit_code, 0) << reference.all();
    ASSERT_EQ(files_in(ref).size(), static_cast<std::size_t>(k_objects));

    // Each round waits until a random number of further objects is logged, then a random few
    // milliseconds more (workers are then loading, rendering or renaming), and kills the run. The
    // moments are counted in logged objects, not in time, so that a fast machine (an object in a few
    // milliseconds) is interrupted as often as a slow one; the rounds stop while a quarter of the
    // collection is still left for the last run.
    // --worker-sharing folder: a worker per object, as the moments above assume (the manifest's
    // default, batches of 32 objects per worker, finished the run within a few milliseconds of a
    // target, before the kill, 2 runs in 10 under load).
    const std::vector<std::string> args{"thumbs", "--manifest", (dir / "m.jsonl").string(), "-o", out.string(), "--size",
                                        "24", "--threads", "2", "--worker-sharing", "folder", "--log", log.string(),
                                        "--resume"};
    std::mt19937 rng(20240611);  // fixed: the same rounds on every run of the test
    const auto lines_in_log = [&] {
        const std::string text = facet_test::read_file(log);
        return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
    };
    // The killed runs' workers become this process's children, to be reaped before the next run.
    ASSERT_EQ(prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
    int interrupted = 0;
    for (int round = 0; round < 6 && lines_in_log() < k_objects * 3 / 4; ++round) {
        const int target = lines_in_log() + std::uniform_int_distribution<int>(1, 4)(rng);
        const int extra_ms = std::uniform_int_distribution<int>(0, 8)(rng);
        const pid_t pid = spawn_facet(args);
        ASSERT_GT(pid, 0);
        int status = 0;
        bool ended = false;
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
        while (!(ended = waitpid(pid, &status, WNOHANG) == pid) && lines_in_log() < target &&
               std::chrono::steady_clock::now() < give_up)
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        if (!ended) {
            std::this_thread::sleep_for(std::chrono::milliseconds(extra_ms));
            kill(pid, SIGKILL);
            while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
        }
        interrupted += WIFSIGNALED(status) ? 1 : 0;
        // Its workers die with it (PR_SET_PDEATHSIG): all gone before the next run starts, however
        // long a loaded machine takes to end them.
        const auto reap_by = std::chrono::steady_clock::now() + std::chrono::seconds(30);
        for (pid_t reaped; (reaped = waitpid(-pid, nullptr, WNOHANG)) != -1 || errno == EINTR;) {
            ASSERT_LT(std::chrono::steady_clock::now(), reap_by) << "a worker outlived its killed run";
            if (reaped == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        ASSERT_EQ(errno, ECHILD);
    }
    EXPECT_GE(interrupted, 4) << "the runs ended before they could be killed";
    const int logged_before = lines_in_log();
    EXPECT_LT(logged_before, k_objects) << "nothing left for the last run";
    const CliRun last = run_facet(args);
    ASSERT_EQ(last.exit_code, 0) << last.all();

    // Exactly one "ok" line per object, every line whole, the outputs those of the lines.
    const std::vector<LogLine> lines = read_log(log);
    std::map<std::string, int> expected;
    for (int i = 0; i < k_objects; ++i) expected["obj-" + std::to_string(i)] = 1;
    EXPECT_EQ(ok_count_by_id(lines), expected);
    for (const LogLine& l : lines) EXPECT_EQ(l.status, "ok") << l.error;
    // No temporary or stray file, and every image the same bytes as the uninterrupted run's.
    std::set<std::string> names;
    for (int i = 0; i < k_objects; ++i) names.insert("obj-" + std::to_string(i) + ".png");
    EXPECT_EQ(files_in(out), names);
    for (const std::string& name : names) {
        ASSERT_TRUE(decode_png(out / name).ok()) << name;
        EXPECT_EQ(facet_test::read_file(out / name), facet_test::read_file(ref / name)) << name;
    }
}

TEST(CliCollection, CommandLineInputsHaveIdsToo) {
    const fs::path dir = temp_dir();
    write_text(dir / "in" / "a.obj", model_obj(1));
    write_text(dir / "in" / "sub" / "a.obj", model_obj(2));
    write_text(dir / "in" / "b.obj", model_obj(3));
    const fs::path log = dir / "log.jsonl";
    std::set<std::string> seen;
    for (int k = 0; k < 2; ++k) {
        const CliRun r = run_facet({"thumbs", (dir / "in").string(), "-o", (dir / "out").string(), "--size", "16", "--shard",
                                    std::to_string(k) + "/2", "--log", log.string()});
        ASSERT_EQ(r.exit_code, 0) << r.all();
    }
    for (const LogLine& l : read_log(log)) {
        EXPECT_EQ(l.outputs, std::vector<std::string>{l.id + ".png"});
        EXPECT_TRUE(seen.insert(l.id).second) << l.id;
    }
    EXPECT_EQ(seen, (std::set<std::string>{"a.obj", "sub__a.obj", "b.obj"}));
    const CliRun again = run_facet({"thumbs", (dir / "in").string(), "-o", (dir / "out").string(), "--size", "16", "--log",
                                    log.string(), "--resume"});
    EXPECT_TRUE(contains(again.err, "0 rendered, 0 failed, 3 skipped")) << again.err;
}

TEST(CliCollection, UsageErrorsAndPrintConfig) {
    const fs::path dir = temp_dir();
    write_text(dir / "a.obj", model_obj(1));
    write_text(dir / "m.txt", "a.obj\n");
    const std::string m = (dir / "m.txt").string(), out = (dir / "out").string();
    for (const std::vector<std::string>& bad :
         {std::vector<std::string>{"thumbs", "-o", out},                                       // no inputs at all
          {"thumbs", (dir / "a.obj").string(), "--manifest", m, "-o", out},                    // both
          {"thumbs", "--manifest", m, "-o", out, "--resume"},                                   // resume without a log
          {"thumbs", "--manifest", m, "-o", out, "--shard", "3/3"},
          {"thumbs", "--manifest", m, "-o", out, "--shard", "x"},
          {"thumbs", "--manifest", (dir / "none.txt").string(), "-o", out}}) {
        const CliRun r = run_facet(bad);
        EXPECT_EQ(r.exit_code, 2) << r.all();
        EXPECT_FALSE(r.err.empty());
        EXPECT_FALSE(fs::exists(out));
    }
    // A log that is not one is refused before anything renders.
    write_text(dir / "notes.txt", "my notes");
    const CliRun notes = run_facet({"thumbs", "--manifest", m, "-o", out, "--log", (dir / "notes.txt").string()});
    EXPECT_EQ(notes.exit_code, 1);
    EXPECT_TRUE(contains(notes.err, "not a facet results log")) << notes.err;
    EXPECT_EQ(facet_test::read_file(dir / "notes.txt"), "my notes");
    EXPECT_FALSE(fs::exists(dir / "out" / "a.obj.png"));

    const CliRun c = run_facet({"thumbs", "--manifest", m, "-o", out, "--shard", "0/1", "--log",
                                (dir / "l.jsonl").string(), "--resume", "--print-config"});
    ASSERT_EQ(c.exit_code, 0) << c.all();
    const std::vector<std::string> expected{"inputs = 1 objects", "manifest = " + m, "shard = 0/1",
                                            "log = " + (dir / "l.jsonl").string(), "resume = yes"};
    for (const std::string& line : expected)
        EXPECT_TRUE(contains(c.out, line + "\n")) << line << "\n" << c.out;
    EXPECT_FALSE(fs::exists(dir / "l.jsonl"));
}

}  // namespace
