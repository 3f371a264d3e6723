// The parts of `facet thumbs`' collections that need no rendering (apps/cli: json, collection,
// results_log): JSON against RFC 8259's edge cases, the shard hash against FNV's published test
// vectors and an independent computation, output names that stay inside the folder and never
// meet, manifests read into entries (bad ones marked, not dropped), log lines written and read
// back, and a torn last line cut before the next one is appended.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "collection.hpp"
#include "json.hpp"
#include "results_log.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet::cli;

fs::path temp_dir() { return facet_test::test_temp_dir("facet_collection"); }

TEST(Json, ParsesWhatRfc8259Allows) {
    const facet::Result<json::Value> v =
        json::parse(R"( {"a": [1, -2.5e3, 0, true, false, null], "s": "x\"\\\/\b\f\n\r\t\u00e9\ud83d\ude00", "o": {}} )");
    ASSERT_TRUE(v.ok()) << v.error().message;
    ASSERT_TRUE(v->is(json::Value::Type::object));
    const json::Value* a = v->find("a");
    ASSERT_TRUE(a && a->is(json::Value::Type::array));
    ASSERT_EQ(a->items.size(), 6u);
    EXPECT_EQ(a->items[0].number, 1);
    EXPECT_EQ(a->items[1].number, -2500);
    EXPECT_TRUE(a->items[3].boolean);
    EXPECT_TRUE(a->items[5].is(json::Value::Type::null));
    EXPECT_EQ(v->find("s")->text, "x\"\\/\b\f\n\r\t\xc3\xa9\xf0\x9f\x98\x80");
    EXPECT_TRUE(v->find("o")->is(json::Value::Type::object));
    EXPECT_EQ(v->find("missing"), nullptr);
}

TEST(Json, RefusesWhatItDoesNotAllowSayingWhere) {
    for (const char* bad : {"", "{", "{\"a\":1,}", "[1,]", "{\"a\" 1}", "{'a':1}", "01", "1.", "-", "1e", "nul",
                            "\"tab\there\"", "\"\\x\"", "\"\\ud800\"", "\"\\udc00\"", "{\"a\":1,\"a\":2}", "{} {}",
                            "\"\xff\"", "\"\xc0\xaf\"", "\"\xed\xa0\x80\"", "1e999"}) {
        const facet::Result<json::Value> v = json::parse(bad);
        EXPECT_FALSE(v.ok()) << bad;
        if (!v.ok()) {
            EXPECT_EQ(v.error().message.rfind("column ", 0), 0u) << v.error().message;
        }
    }
    EXPECT_NE(json::parse("{\"a\":1,}").error().message.find("column 8"), std::string::npos)
        << json::parse("{\"a\":1,}").error().message;
    std::string deep(65, '[');
    deep += std::string(65, ']');
    EXPECT_FALSE(json::parse(deep).ok());
    std::string ok_deep(64, '[');
    ok_deep += std::string(64, ']');
    EXPECT_TRUE(json::parse(ok_deep).ok());
}

TEST(Json, QuoteRoundTripsAndReplacesBytesThatAreNotUtf8) {
    for (const std::string& s : {std::string("plain"), std::string("q\"b\\s/"), std::string("\x01\n\x1f"),
                                std::string("\xc3\xa9\xf0\x9f\x98\x80"), std::string("a\0b", 3)}) {
        const facet::Result<json::Value> back = json::parse(json::quote(s));
        ASSERT_TRUE(back.ok()) << json::quote(s);
        EXPECT_EQ(back->text, s);
    }
    EXPECT_EQ(json::quote("a\xff"
                          "b"),
              "\"a\xef\xbf\xbd"
              "b\"");
    EXPECT_TRUE(json::valid_utf8("\xc3\xa9"));
    EXPECT_FALSE(json::valid_utf8("\xc3"));
    EXPECT_FALSE(json::valid_utf8("\xf4\x90\x80\x80"));  // above U+10FFFF
}

TEST(Shards, HashIsFnv1aThenFmix64) {
    // FNV-1a's published test vectors.
    EXPECT_EQ(fnv1a_64(""), 0xcbf29ce484222325ull);
    EXPECT_EQ(fnv1a_64("a"), 0xaf63dc4c8601ec8cull);
    EXPECT_EQ(fnv1a_64("foobar"), 0x85944171f73967e8ull);
    // The documented Python (README, "Collections") gives these.
    EXPECT_EQ(shard_hash(""), 0xefd01f60ba992926ull);
    EXPECT_EQ(shard_hash("a"), 0x82a2a958a9bece5bull);
    EXPECT_EQ(shard_hash("chair-01"), 0xc3ca3430caafdd74ull);
    EXPECT_EQ(shard_hash("\xc3\xa9/x"), 0x15d7385efe3a3403ull);
}

TEST(Shards, EveryIdInExactlyOneShardAndTheShardsAreEven) {
    // 3000 ids that differ only in their last characters: each shard of 3 and of 7 holds its
    // share within 10% (a hash without the finalizer puts them all into one).
    for (const std::uint32_t n : {3u, 7u}) {
        std::vector<int> count(n);
        for (int i = 0; i < 3000; ++i) {
            const std::string id = "obj-" + std::to_string(i);
            const std::uint32_t k = shard_of(id, n);
            ASSERT_LT(k, n);
            ++count[k];
        }
        for (const int c : count) EXPECT_NEAR(c, 3000.0 / n, 300.0 / n) << n;
    }
    EXPECT_EQ(shard_of("anything", 1), 0u);
}

TEST(Shards, ParseShard) {
    const facet::Result<Shard> s = parse_shard("2/5");
    ASSERT_TRUE(s.ok());
    EXPECT_EQ(s->index, 2u);
    EXPECT_EQ(s->count, 5u);
    for (const char* bad : {"5/5", "1/0", "0", "/3", "1/", "a/3", "-1/3", "1/3/4", "1 /3", "0x1/3", "1/99999999999"}) {
        const facet::Result<Shard> b = parse_shard(bad);
        EXPECT_FALSE(b.ok()) << bad;
        if (!b.ok()) {
            EXPECT_NE(b.error().message.find("--shard"), std::string::npos);
        }
    }
}

TEST(OutputNames, StayInsideTheFolderAndNeverMeet) {
    EXPECT_EQ(*output_stem_for_id("chair-01_v2.x~"), "chair-01_v2.x~");
    EXPECT_EQ(*output_stem_for_id("a/b"), "a%2Fb");
    EXPECT_EQ(*output_stem_for_id(".."), "%2E.");
    EXPECT_EQ(*output_stem_for_id(".hidden"), "%2Ehidden");
    EXPECT_EQ(*output_stem_for_id("../../etc/passwd"), "%2E.%2F..%2Fetc%2Fpasswd");
    EXPECT_EQ(*output_stem_for_id("a b%"), "a%20b%25");
    EXPECT_EQ(*output_stem_for_id("\xc3\xa9"), "%C3%A9");
    EXPECT_EQ(*output_stem_for_id("C:\\x"), "C%3A%5Cx");
    EXPECT_FALSE(output_stem_for_id("").ok());
    EXPECT_FALSE(output_stem_for_id("\xff").ok());
    EXPECT_TRUE(output_stem_for_id(std::string(k_max_stem, 'a')).ok());
    EXPECT_FALSE(output_stem_for_id(std::string(k_max_stem + 1, 'a')).ok());
    EXPECT_FALSE(output_stem_for_id(std::string(k_max_stem / 3 + 1, '/')).ok());

    // Every byte value in every position: a stem is one path component, not "." or "..", made of
    // the kept characters and %XX only; distinct ids give distinct stems.
    std::set<std::string> stems;
    std::vector<std::string> ids;
    for (int a = 0; a < 256; ++a)
        for (const char* tail : {"", ".", "/", "%2F"}) ids.push_back(std::string(1, static_cast<char>(a)) + tail);
    for (const std::string& id : ids) {
        const facet::Result<std::string> stem = output_stem_for_id(id);
        if (!stem.ok()) continue;  // bytes that are not UTF-8 on their own
        EXPECT_EQ(stem->find('/'), std::string::npos) << id;
        EXPECT_NE(*stem, ".");
        EXPECT_NE(*stem, "..");
        EXPECT_NE(stem->front(), '.');
        EXPECT_EQ(stem->find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_.~%"),
                  std::string::npos)
            << *stem;
        EXPECT_TRUE(stems.insert(*stem).second) << "two ids share the stem " << *stem;
        EXPECT_EQ(fs::path("/out") / (*stem + ".png"), fs::path("/out/" + *stem + ".png"));
    }
    EXPECT_GT(stems.size(), 500u);
}

std::vector<ObjectEntry> manifest_of(const std::string& text, Shard shard = {}) {
    const fs::path dir = temp_dir();
    const std::string path = facet_test::write_file(dir / "m.txt", text);
    facet::Result<std::vector<ObjectEntry>> entries = read_manifest(path, shard);
    EXPECT_TRUE(entries.ok());
    return entries.ok() ? *entries : std::vector<ObjectEntry>{};
}

TEST(Manifest, PathsOnePerLineRelativeToTheManifest) {
    const std::vector<ObjectEntry> e = manifest_of("# a comment\n\n  models/a.obj  \r\n/abs/b.stl\n");
    ASSERT_EQ(e.size(), 2u);
    const fs::path dir = temp_dir();
    EXPECT_EQ(e[0].id, "models/a.obj");
    EXPECT_EQ(e[0].path, (dir / "models/a.obj").string());
    EXPECT_EQ(e[0].stem, "models%2Fa.obj");
    EXPECT_EQ(e[0].line, 3u);
    EXPECT_EQ(e[0].reason, FailReason::none);
    EXPECT_EQ(e[1].id, "/abs/b.stl");
    EXPECT_EQ(e[1].path, "/abs/b.stl");
    EXPECT_EQ(e[1].stem, "%2Fabs%2Fb.stl");
}

TEST(Manifest, JsonLinesWithIdsAndPerObjectOptions) {
    const std::vector<ObjectEntry> e = manifest_of(
        "{\"id\": \"chair\", \"path\": \"c.obj\", \"size\": 512, \"up_axis\": \"z\"}\n"
        "{\"path\": \"d.glb\", \"size\": \"320x200\", \"views\": \"orbit:8:30\", \"passes\": [\"color\", \"depth\"]}\n"
        "{\"id\": \"e\", \"path\": \"e.stl\", \"passes\": \"color, normal\"}\n"
        "{\"id\": \"f\", \"path\": \"f.stl\", \"views\": \"file:rigs/cameras.json\"}\n"
        "{\"id\": \"g\", \"path\": \"g.stl\", \"views\": \"file:/abs/transforms.json\"}\n");
    ASSERT_EQ(e.size(), 5u);
    EXPECT_EQ(e[0].id, "chair");
    EXPECT_EQ(e[0].stem, "chair");
    EXPECT_EQ(e[0].options.size, "512");
    EXPECT_EQ(e[0].options.up_axis, "z");
    EXPECT_FALSE(e[0].options.views.has_value());
    EXPECT_EQ(e[1].id, "d.glb");  // no id: the path as written
    EXPECT_EQ(e[1].options.size, "320x200");
    EXPECT_EQ(e[1].options.views, "orbit:8:30");
    EXPECT_EQ(e[1].options.passes, (std::vector<std::string>{"color", "depth"}));
    EXPECT_EQ(e[2].options.passes, (std::vector<std::string>{"color", "normal"}));
    // A cameras file, as a model's path, is relative to the manifest's folder.
    EXPECT_EQ(e[3].options.views, "file:" + (fs::path(e[3].path).parent_path() / "rigs" / "cameras.json").string());
    EXPECT_EQ(e[4].options.views, "file:/abs/transforms.json");
    for (const ObjectEntry& x : e) EXPECT_EQ(x.reason, FailReason::none) << x.error;
}

TEST(Manifest, BadEntriesAreMarkedWithTheirLineNotDropped) {
    const std::vector<ObjectEntry> e = manifest_of(
        "{\"id\": \"a\", \"path\": \"a.obj\"}\n"
        "{\"id\": \"a\", \"path\": \"other.obj\"}\n"     // duplicate id
        "{\"id\": \"b\", \"path\": \"b.obj\", \"colour\": 1}\n"  // unknown key
        "{\"id\": \"c\", \"path\": \"c.obj\", \"size\": 2.5}\n"  // not a whole number
        "{\"id\": \"d\", \"path\": \"d.obj\", \"size\": true}\n"
        "{\"id\": 7, \"path\": \"e.obj\"}\n"              // id not a string
        "{\"id\": \"f\"}\n"                               // no path
        "{\"id\": \"g\", \"path\": \"\"}\n"
        "{\"id\": \"h\", \"path\": \"h.obj\", \"passes\": []}\n"
        "{\"id\": \"i\", \"path\": \"i.obj\"\n"             // torn
        "[1, 2]\n"
        "{\"id\": \"\", \"path\": \"j.obj\"}\n"           // empty id
        "{\"id\": \"k\", \"path\": \"k.obj\"}\n");
    ASSERT_EQ(e.size(), 13u);
    const std::string m = (temp_dir() / "m.txt").string();
    EXPECT_EQ(e[0].reason, FailReason::none);
    EXPECT_EQ(e[1].reason, FailReason::duplicate_id);
    EXPECT_EQ(e[1].error, m + ":2: duplicate id \"a\" (first on line 1)");
    for (std::size_t i = 2; i < 12; ++i) {
        EXPECT_EQ(e[i].reason, FailReason::bad_entry) << i;
        EXPECT_EQ(e[i].error.rfind(m + ":" + std::to_string(i + 1) + ": ", 0), 0u) << e[i].error;
        EXPECT_EQ(e[i].line, i + 1);
    }
    EXPECT_NE(e[2].error.find("unknown key \"colour\""), std::string::npos) << e[2].error;
    EXPECT_EQ(e[2].id, "b");  // kept: the line claims it
    EXPECT_NE(e[6].error.find("no \"path\""), std::string::npos) << e[6].error;
    EXPECT_NE(e[9].error.find("not valid JSON: column"), std::string::npos) << e[9].error;
    EXPECT_EQ(e[9].id, "");
    EXPECT_EQ(e[12].reason, FailReason::none);
}

TEST(Manifest, AShardKeepsItsEntriesAndItsDuplicates) {
    std::string text;
    for (int i = 0; i < 12; ++i) text += "{\"id\": \"chair-" + std::string(i < 10 ? "0" : "") + std::to_string(i) + "\", \"path\": \"x.obj\"}\n";
    text += "{\"id\": \"chair-06\", \"path\": \"y.obj\"}\n";
    text += "{not json\n";
    // The expected split, computed apart from facet (README's Python): a fixed manifest splits the
    // same way on every machine and every run.
    const std::map<std::uint32_t, std::set<std::string>> expected = {
        {0, {"chair-06"}},
        {1, {"chair-03", "chair-04", "chair-05", "chair-07", "chair-08", "chair-11"}},
        {2, {"chair-00", "chair-01", "chair-02", "chair-09", "chair-10"}},
    };
    std::size_t bad_lines = 0;
    for (std::uint32_t k = 0; k < 3; ++k) {
        std::set<std::string> ok;
        std::size_t duplicates = 0;
        for (const ObjectEntry& e : manifest_of(text, {k, 3})) {
            if (e.reason == FailReason::none) ok.insert(e.id);
            duplicates += e.reason == FailReason::duplicate_id;
            bad_lines += e.reason == FailReason::bad_entry;
        }
        EXPECT_EQ(ok, expected.at(k)) << k;
        EXPECT_EQ(duplicates, k == 0 ? 1u : 0u) << k;
    }
    EXPECT_EQ(bad_lines, 1u);  // one shard, and one only, reports a line without an id
}

TEST(Manifest, SelectedLinesReadAsInTheWholeManifest) {
    const std::string text =
        "# objects\n"
        "{\"id\": \"a\", \"path\": \"a.obj\"}\n"
        "\n"
        "{\"id\": \"b\", \"path\": \"b.obj\", \"size\": 64}\n"
        "{\"id\": \"a\", \"path\": \"c.obj\"}\n"
        "{broken\n"
        "{\"id\": \"d\", \"path\": \"d.obj\"}";  // no final newline
    const std::vector<ObjectEntry> whole = manifest_of(text);
    ASSERT_EQ(whole.size(), 5u);
    const fs::path path = temp_dir() / "m.txt";
    facet_test::write_file(path, text);
    // The byte offset of each line, as facet.distributed computes them.
    std::vector<ManifestLine> all;
    for (std::size_t offset = 0, number = 1; offset <= text.size(); ++number) {
        all.push_back({offset, number});
        const std::size_t end = text.find('\n', offset);
        offset = end == std::string::npos ? text.size() + 1 : end + 1;
    }
    const auto read = [&](std::vector<ManifestLine> only) {
        facet::Result<std::vector<ObjectEntry>> e = read_manifest(path.string(), {}, &only);
        EXPECT_TRUE(e.ok()) << (e.ok() ? "" : e.error().message);
        return e.ok() ? *e : std::vector<ObjectEntry>{};
    };
    const auto same = [](const ObjectEntry& x, const ObjectEntry& y) {
        return x.id == y.id && x.path == y.path && x.stem == y.stem && x.line == y.line && x.origin == y.origin &&
               x.options.size == y.options.size && x.reason == y.reason && x.error == y.error;
    };
    // Every line, given in any order: the whole manifest's entries (comments and blanks skip).
    std::vector<ManifestLine> shuffled(all.rbegin(), all.rend());
    const std::vector<ObjectEntry> every = read(shuffled);
    ASSERT_EQ(every.size(), whole.size());
    for (std::size_t i = 0; i < whole.size(); ++i) EXPECT_TRUE(same(every[i], whole[i])) << whole[i].origin;
    // Lines 4, 5 and 7 alone: the same entries as in the whole (line 5 is no duplicate without 2).
    const std::vector<ObjectEntry> some = read({all[3], all[4], all[6]});
    ASSERT_EQ(some.size(), 3u);
    EXPECT_TRUE(same(some[0], whole[1]));
    EXPECT_EQ(some[1].reason, facet::cli::FailReason::none);
    EXPECT_EQ(some[1].id, "a");
    EXPECT_TRUE(same(some[2], whole[4]));

    std::vector<ManifestLine> inside{{all[1].offset + 3, 2}};
    EXPECT_FALSE(read_manifest(path.string(), {}, &inside).ok());
    std::vector<ManifestLine> past{{text.size() + 10, 9}};
    EXPECT_FALSE(read_manifest(path.string(), {}, &past).ok());
    EXPECT_FALSE(read_manifest("-", {}, &all).ok());
    ASSERT_TRUE(parse_manifest_lines("0:1,35:3").ok());
    EXPECT_EQ(parse_manifest_lines("0:1,35:3")->at(1).offset, 35u);
    EXPECT_EQ(parse_manifest_lines("0:1,35:3")->at(1).number, 3u);
    for (const char* bad : {"", "1", "1:", ":1", "1:0", "a:1", "1:2,", "1:2;3:4", "-1:1"})
        EXPECT_FALSE(parse_manifest_lines(bad).ok()) << bad;
}

TEST(Manifest, UnreadableManifestIsAnError) {
    const fs::path dir = temp_dir();
    const facet::Result<std::vector<ObjectEntry>> missing = read_manifest((dir / "none.jsonl").string(), {});
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("none.jsonl"), std::string::npos);
    EXPECT_FALSE(read_manifest(dir.string(), {}).ok());
}

// The options hash covers the settings that shape the image and the object's views and passes,
// and none of those that only say how the run goes, the sandbox (the kernel's) among them.
TEST(OptionsHash, ChangesWithTheImageOnly) {
    const std::string config = "# facet thumbs: the settings in effect\nsize = 24x24\nshading = lambert\n"
                               "threads = 2\nisa = avx2\ntile-size = 64\nbatch-triangles = 4096\nload-threads = 1\n"
                               "isolation = worker-process\nsandbox = seccomp, landlock (ABI 3)\ntimeout = 60\n"
                               "max-memory = 4G\n";
    const ObjectOptions none;
    const std::string hash = options_hash(config, none);
    EXPECT_EQ(hash.size(), 16u);
    EXPECT_EQ(hash.find_first_not_of("0123456789abcdef"), std::string::npos) << hash;
    const auto with = [&](const std::string& key, const std::string& value) {
        const std::size_t at = config.find("\n" + key + " = ") + key.size() + 4;
        return config.substr(0, at) + value + config.substr(config.find('\n', at));
    };
    for (const auto& [key, value] : std::map<std::string, std::string>{
             {"threads", "1"}, {"isa", "scalar"}, {"tile-size", "32"}, {"batch-triangles", "100"},
             {"load-threads", "2"}, {"isolation", "none"}, {"sandbox", "seccomp (this kernel has no Landlock)"},
             {"timeout", "0"}, {"max-memory", "0"}})
        EXPECT_EQ(options_hash(with(key, value), none), hash) << key;
    EXPECT_NE(options_hash(with("size", "28x28"), none), hash);
    EXPECT_NE(options_hash(with("shading", "flat"), none), hash);
    EXPECT_NE(options_hash(config + "background = 1,0,0\n", none), hash);
    ObjectOptions views, passes;
    views.views = "orbit:8";
    passes.passes = {"color", "depth"};
    EXPECT_NE(options_hash(config, views), hash);
    EXPECT_NE(options_hash(config, passes), hash);
    EXPECT_NE(options_hash(config, views), options_hash(config, passes));
}

TEST(ResultsLog, LinesAreJsonAndReadBack) {
    LogRecord ok;
    ok.id = "a/\"b\"";
    ok.path = "/m/a.obj";
    ok.line = 3;
    ok.triangles = 12;
    ok.load_ms = 1.5;
    ok.render_ms = 0.25;
    ok.write_ms = 0.125;
    ok.total_ms = 2;
    ok.outputs = {"a%2F%22b%22.png"};
    ok.options_hash = "0123456789abcdef";
    const std::string line = format_log_line(ok);
    EXPECT_EQ(line,
              "{\"id\":\"a/\\\"b\\\"\",\"path\":\"/m/a.obj\",\"line\":3,\"status\":\"ok\",\"reason\":null,\"error\":null,"
              "\"triangles\":12,\"load_ms\":1.500,\"render_ms\":0.250,\"write_ms\":0.125,\"total_ms\":2.000,"
              "\"outputs\":[\"a%2F%22b%22.png\"],\"options_hash\":\"0123456789abcdef\"}\n");
    LogRecord failed;
    failed.path = "x";
    failed.reason = FailReason::timed_out;
    failed.error = "x: gave up after 1 s\xff";
    const std::string failed_line = format_log_line(failed);
    const facet::Result<json::Value> f = json::parse(failed_line);
    ASSERT_TRUE(f.ok()) << failed_line;
    EXPECT_TRUE(f->find("id")->is(json::Value::Type::null));
    EXPECT_EQ(f->find("status")->text, "failed");
    EXPECT_EQ(f->find("reason")->text, "timed_out");
    EXPECT_TRUE(f->find("triangles")->is(json::Value::Type::null));

    const fs::path dir = temp_dir();
    const std::string path = (dir / "logs" / "run.jsonl").string();
    {
        facet::Result<LogWriter> w = LogWriter::open(path);  // creates the folder
        ASSERT_TRUE(w.ok()) << w.error().message;
        ASSERT_TRUE(w->append(line).ok());
        ASSERT_TRUE(w->append(failed_line).ok());
        LogRecord again = ok;
        again.options_hash = "fedcba9876543210";  // a later render of the same id: it wins
        ASSERT_TRUE(w->append(format_log_line(again)).ok());
    }
    const facet::Result<LogContents> log = read_log(path);
    ASSERT_TRUE(log.ok());
    EXPECT_EQ(log->lines, 3u);
    EXPECT_EQ(log->unreadable, 0u);
    EXPECT_FALSE(log->torn_tail);
    ASSERT_EQ(log->finished.size(), 1u);
    EXPECT_EQ(log->finished.at("a/\"b\"").options_hash, "fedcba9876543210");
    EXPECT_EQ(log->finished.at("a/\"b\"").outputs, ok.outputs);
    // A missing log reads as empty.
    const facet::Result<LogContents> none = read_log((dir / "none.jsonl").string());
    ASSERT_TRUE(none.ok());
    EXPECT_TRUE(none->finished.empty());
}

TEST(ResultsLog, ATornLastLineIsSkippedThenCut) {
    const fs::path dir = temp_dir();
    LogRecord r;
    r.id = "done";
    r.options_hash = "h";
    r.outputs = {"done.png"};
    const std::string complete = format_log_line(r);
    r.id = "torn";
    const std::string torn = format_log_line(r).substr(0, 40);  // a writer killed mid-line
    const std::string path = facet_test::write_file(dir / "log.jsonl", complete + "garbage that is not json\n" + torn);

    const facet::Result<LogContents> before = read_log(path);
    ASSERT_TRUE(before.ok());
    EXPECT_TRUE(before->torn_tail);
    EXPECT_EQ(before->lines, 2u);
    EXPECT_EQ(before->unreadable, 1u);
    EXPECT_EQ(before->finished.count("done"), 1u);
    EXPECT_EQ(before->finished.count("torn"), 0u);

    r.id = "next";
    const std::string next = format_log_line(r);
    {
        facet::Result<LogWriter> w = LogWriter::open(path);
        ASSERT_TRUE(w.ok());
        ASSERT_TRUE(w->append(next).ok());
    }
    EXPECT_EQ(facet_test::read_file(path), complete + "garbage that is not json\n" + next);
    // A log that is one torn line: cut to nothing, then the line.
    const std::string only_torn = facet_test::write_file(dir / "only.jsonl", torn);
    {
        facet::Result<LogWriter> w = LogWriter::open(only_torn);
        ASSERT_TRUE(w.ok());
        ASSERT_TRUE(w->append(next).ok());
    }
    EXPECT_EQ(facet_test::read_file(only_torn), next);
}

TEST(ResultsLog, RefusesAFileThatIsNotALog) {
    const fs::path dir = temp_dir();
    const std::string text = "precious text without a final newline";
    const std::string path = facet_test::write_file(dir / "notes.txt", text);
    const facet::Result<LogWriter> w = LogWriter::open(path);
    ASSERT_FALSE(w.ok());
    EXPECT_NE(w.error().message.find("not a facet results log"), std::string::npos) << w.error().message;
    EXPECT_EQ(facet_test::read_file(path), text);
    EXPECT_FALSE(LogWriter::open(dir.string()).ok());  // a folder
}

}  // namespace
