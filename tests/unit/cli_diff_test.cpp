// `facet diff` and `facet render --reference` as a script sees them: exit codes, the summary line,
// the JSON, the difference image. SSIM is checked against closed forms and against an independent
// implementation here (a direct sum over each 11x11 window, no separable filtering, no ring of rows).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "facet/io.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using facet::Image;
using facet::Rgba8;
using facet_test::CliRun;
using facet_test::run_facet;

fs::path temp_dir() { return facet_test::test_temp_dir("facet_cli_diff"); }

// A 40x30 image with a gradient and a pattern, so SSIM's windows see structure.
Image pattern(int w = 40, int h = 30) {
    Image img{w, h, std::vector<Rgba8>(static_cast<std::size_t>(w) * h)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.at(x, y) = {static_cast<std::uint8_t>(x * 6), static_cast<std::uint8_t>(y * 8),
                            static_cast<std::uint8_t>((x / 4 + y / 4) % 2 ? 200 : 40), 255};
    return img;
}

std::string save(const fs::path& path, const Image& img) {
    EXPECT_TRUE(facet::write_png(path.string(), img).ok()) << path;
    return path.string();
}

CliRun diff(const std::vector<std::string>& args) {
    std::vector<std::string> all = {"diff"};
    all.insert(all.end(), args.begin(), args.end());
    return run_facet(all);
}

// A number from the JSON line: "key":value.
double json_value(const std::string& json, const std::string& key) {
    std::smatch m;
    EXPECT_TRUE(std::regex_search(json, m, std::regex("\"" + key + "\":([-0-9.e]+|null|true|false)"))) << key << " in " << json;
    if (m.empty() || m[1] == "null") return NAN;
    if (m[1] == "true") return 1;
    if (m[1] == "false") return 0;
    return std::stod(m[1]);
}

// SSIM by Wang et al.'s definition, written directly: for every 11x11 window inside the image, the
// Gaussian-weighted (sigma 1.5, weights summing to 1) means, variances and covariance of the two
// images' channel values, then the mean of the windows' SSIM over the window positions and over the
// colour channels (R, G, B: the images are opaque).
double reference_ssim(const Image& a, const Image& b) {
    double w2[11][11], sum = 0;
    for (int i = 0; i < 11; ++i)
        for (int j = 0; j < 11; ++j) sum += w2[i][j] = std::exp(-((i - 5) * (i - 5) + (j - 5) * (j - 5)) / 4.5);
    const double c1 = 6.5025, c2 = 58.5225;
    double total = 0;
    int count = 0;
    for (int c = 0; c < 3; ++c)
        for (int y0 = 0; y0 + 11 <= a.height; ++y0)
            for (int x0 = 0; x0 + 11 <= a.width; ++x0) {
                auto value = [c](const Image& img, int x, int y) {
                    const Rgba8 p = img.at(x, y);
                    return static_cast<double>(c == 0 ? p.r : c == 1 ? p.g : p.b);
                };
                double ma = 0, mb = 0;
                for (int i = 0; i < 11; ++i)
                    for (int j = 0; j < 11; ++j) {
                        ma += w2[i][j] / sum * value(a, x0 + j, y0 + i);
                        mb += w2[i][j] / sum * value(b, x0 + j, y0 + i);
                    }
                double va = 0, vb = 0, cov = 0;
                for (int i = 0; i < 11; ++i)
                    for (int j = 0; j < 11; ++j) {
                        const double da = value(a, x0 + j, y0 + i) - ma, db = value(b, x0 + j, y0 + i) - mb;
                        va += w2[i][j] / sum * da * da, vb += w2[i][j] / sum * db * db, cov += w2[i][j] / sum * da * db;
                    }
                total += (2 * ma * mb + c1) * (2 * cov + c2) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
                ++count;
            }
    return total / count;
}

TEST(CliDiff, IdenticalImagesMatch) {
    const fs::path dir = temp_dir();
    const std::string a = save(dir / "a.png", pattern()), b = save(dir / "b.png", pattern());
    const CliRun r = diff({a, b});
    EXPECT_EQ(r.exit_code, 0) << r.all();
    EXPECT_NE(r.out.find("facet diff: " + a + " vs " + b + ": 40x30, 0 of 1200 pixels differ by more than 0 "
                         "(largest difference R 0 G 0 B 0 A 0), PSNR inf, SSIM 1.000000: match"),
              std::string::npos)
        << r.out;
    const CliRun j = diff({a, b, "--json"});
    EXPECT_EQ(j.exit_code, 0);
    EXPECT_EQ(json_value(j.out, "pass"), 1);
    EXPECT_TRUE(std::isnan(json_value(j.out, "psnr"))) << "infinite PSNR is null in JSON: " << j.out;
    EXPECT_EQ(json_value(j.out, "ssim"), 1);
}

TEST(CliDiff, OnePixelChangedFailsUnlessAllowed) {
    const fs::path dir = temp_dir();
    Image changed = pattern();
    changed.at(7, 5).r = static_cast<std::uint8_t>(changed.at(7, 5).r + 40);
    const std::string a = save(dir / "a.png", pattern()), b = save(dir / "b.png", changed);
    const fs::path picture = dir / "d.png";
    const CliRun r = diff({a, b, "--diff-image", picture.string()});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_NE(r.out.find(": 40x30, 1 of 1200 pixels differ by more than 0 (largest difference R 40 G 0 B 0 A 0), PSNR "),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find(": MISMATCH (1 pixels differ by more than 0, 0 allowed)"), std::string::npos) << r.out;
    // The picture: red where they differ, a dimmed grey copy of A elsewhere.
    const facet_test::DecodedPng d = facet_test::decode_png(picture);
    ASSERT_TRUE(d.ok()) << d.error;
    ASSERT_EQ(d.width, 40u);
    EXPECT_EQ(d.at(7, 5), (Rgba8{255, 0, 0, 255}));
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            if (x == 7 && y == 5) continue;
            const Rgba8 p = d.at(x, y);
            ASSERT_TRUE(p.r == p.g && p.g == p.b && p.a == 255 && p.r < 160) << x << "," << y;  // dimmed grey
        }
    EXPECT_LT(d.at(0, 0).r, d.at(39, 29).r);  // A's dark corner darker than its bright one
    // Allowed by the thresholds: one pixel, a tolerance of 40, or a share of the pixels.
    EXPECT_EQ(diff({a, b, "--threshold", "pixels=1"}).exit_code, 0);
    EXPECT_EQ(diff({a, b, "--threshold", "diff=40"}).exit_code, 0);
    EXPECT_EQ(diff({a, b, "--threshold", "diff=39"}).exit_code, 1);
    EXPECT_EQ(diff({a, b, "--threshold", "pixels=0.1%"}).exit_code, 0);     // 1.2 pixels of 1200
    EXPECT_EQ(diff({a, b, "--threshold", "pixels=0.05%"}).exit_code, 1);    // 0.6
    EXPECT_EQ(diff({a, b, "--threshold", "ssim=0.99"}).exit_code, 0);       // pixels not counted
    const CliRun strict = diff({a, b, "--threshold", "ssim=1"});
    EXPECT_EQ(strict.exit_code, 1);
    EXPECT_NE(strict.out.find("MISMATCH (SSIM 0.9"), std::string::npos) << strict.out;
    const CliRun j = diff({a, b, "--json"});
    EXPECT_EQ(json_value(j.out, "differing_pixels"), 1);
    EXPECT_EQ(json_value(j.out, "pass"), 0);
    // PSNR: one channel of one pixel off by 40, over 3 channels of 1200 pixels.
    EXPECT_NEAR(json_value(j.out, "psnr"), 10 * std::log10(255.0 * 255 / (40.0 * 40 / 3600)), 1e-3);
}

TEST(CliDiff, SizeMismatchFails) {
    const fs::path dir = temp_dir();
    const std::string a = save(dir / "a.png", pattern(40, 30)), b = save(dir / "b.png", pattern(30, 40));
    const CliRun r = diff({a, b, "--diff-image", (dir / "d.png").string()});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_NE(r.out.find(": sizes differ (40x30 and 30x40): MISMATCH"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir / "d.png"));
    EXPECT_NE(r.err.find("no difference image"), std::string::npos) << r.err;
    EXPECT_EQ(json_value(diff({a, b, "--json"}).out, "same_size"), 0);
}

TEST(CliDiff, AlphaOnlyChangeFails) {
    const fs::path dir = temp_dir();
    Image changed = pattern();
    changed.at(0, 0).a = 200;
    const std::string a = save(dir / "a.png", pattern()), b = save(dir / "b.png", changed);
    const CliRun r = diff({a, b});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_NE(r.out.find("1 of 1200 pixels differ by more than 0 (largest difference R 0 G 0 B 0 A 55)"),
              std::string::npos)
        << r.out;
}

TEST(CliDiff, BrokenOrMissingFilesAndBadUsageExitTwo) {
    const fs::path dir = temp_dir();
    const std::string a = save(dir / "a.png", pattern());
    const std::string broken = facet_test::write_file(dir / "broken.png", "\x89PNG\r\n\x1a\nnot really");
    const CliRun r = diff({a, broken});
    EXPECT_EQ(r.exit_code, 2) << r.all();
    EXPECT_NE(r.err.find(broken), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
    const CliRun missing = diff({(dir / "none.png").string(), a});
    EXPECT_EQ(missing.exit_code, 2) << missing.all();
    EXPECT_NE(missing.err.find("none.png"), std::string::npos) << missing.err;
    const CliRun folder = diff({a, dir.string()});  // said "not a valid PNG file (stream error)"
    EXPECT_EQ(folder.exit_code, 2) << folder.all();
    EXPECT_NE(folder.err.find(dir.string() + ": is a directory"), std::string::npos) << folder.err;
    EXPECT_EQ(diff({a}).exit_code, 2);
    for (const char* bad : {"ssim", "diff=256", "diff=1.5", "pixels=-1", "ssim=2", "colour=1", "diff=1%", "psnr=x"}) {
        const CliRun t = diff({a, a, "--threshold", bad});
        EXPECT_EQ(t.exit_code, 2) << bad << ": " << t.all();
        EXPECT_NE(t.err.find("--threshold"), std::string::npos) << t.err;
    }
}

TEST(CliDiff, SsimMatchesClosedFormsAndAnIndependentImplementation) {
    const fs::path dir = temp_dir();
    // Two flat images: every window's variances and covariance are 0, so SSIM is the luminance
    // term alone, (2 a b + C1) / (a^2 + b^2 + C1), C1 = (0.01 * 255)^2.
    const Image flat_a{20, 20, std::vector<Rgba8>(400, Rgba8{100, 100, 100, 255})};
    const Image flat_b{20, 20, std::vector<Rgba8>(400, Rgba8{150, 150, 150, 255})};
    const CliRun flat = diff({save(dir / "fa.png", flat_a), save(dir / "fb.png", flat_b), "--json"});
    const double c1 = 6.5025;
    EXPECT_NEAR(json_value(flat.out, "ssim"), (2 * 100.0 * 150 + c1) / (100.0 * 100 + 150.0 * 150 + c1), 1e-7) << flat.out;

    // Noise on a pattern, against the direct definition.
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> noise(-25, 25);
    const Image a = pattern(48, 36);
    Image b = a;
    for (Rgba8& p : b.pixels) {
        p.r = static_cast<std::uint8_t>(std::clamp(p.r + noise(rng), 0, 255));
        p.g = static_cast<std::uint8_t>(std::clamp(p.g + noise(rng), 0, 255));
        p.b = static_cast<std::uint8_t>(std::clamp(p.b + noise(rng), 0, 255));
    }
    const CliRun noisy = diff({save(dir / "na.png", a), save(dir / "nb.png", b), "--json"});
    const double want = reference_ssim(a, b);
    EXPECT_GT(want, 0.2);
    EXPECT_LT(want, 0.95);
    EXPECT_NEAR(json_value(noisy.out, "ssim"), want, 1e-7) << noisy.out;
}

TEST(CliRenderReference, WritesComparesAndReportsTheDifference) {
    const fs::path dir = temp_dir();
    const std::string out = (dir / "out.png").string(), ref = (dir / "ref.png").string();
    const std::vector<std::string> base = {"render", "--size", "64x48", "-o", out, "--reference", ref};
    auto with = [&](std::vector<std::string> more) {
        std::vector<std::string> args = base;
        args.insert(args.end(), more.begin(), more.end());
        return run_facet(args);
    };
    // A missing reference is an error, before anything is rendered.
    const CliRun missing = with({});
    EXPECT_EQ(missing.exit_code, 2) << missing.all();
    EXPECT_NE(missing.err.find(ref + " does not exist (--update-reference writes it)"), std::string::npos) << missing.err;
    EXPECT_FALSE(fs::exists(out));
    // So is a folder, with or without --update-reference (it rendered, then failed to read it as a PNG).
    const std::string folder = (dir / "refs").string();
    fs::create_directories(folder);
    for (bool update : {false, true}) {
        std::vector<std::string> args = {"render", "--size", "64x48", "-o", out, "--reference", folder};
        if (update) args.push_back("--update-reference");
        const CliRun r = run_facet(args);
        EXPECT_EQ(r.exit_code, 2) << r.all();
        EXPECT_NE(r.err.find(folder + " is a directory, not a PNG file"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out));
    }
    // --update-reference writes it, and says so.
    const CliRun first = with({"--update-reference"});
    ASSERT_EQ(first.exit_code, 0) << first.all();
    EXPECT_NE(first.err.find("wrote the reference " + ref), std::string::npos) << first.err;
    ASSERT_TRUE(fs::exists(ref));
    EXPECT_TRUE(facet_test::decode_png(ref).rgba == facet_test::decode_png(out).rgba);
    // The same render matches.
    const CliRun same = with({"--threads", "1"});
    EXPECT_EQ(same.exit_code, 0) << same.all();
    EXPECT_NE(same.err.find(": match"), std::string::npos) << same.err;
    // Another shading does not: exit 1, and the difference image next to the output.
    const CliRun other = with({"--shading", "normals"});
    EXPECT_EQ(other.exit_code, 1) << other.all();
    EXPECT_NE(other.err.find("MISMATCH"), std::string::npos) << other.err;
    EXPECT_NE(other.err.find("where they differ: " + (dir / "out.diff.png").string()), std::string::npos) << other.err;
    EXPECT_TRUE(facet_test::decode_png(dir / "out.diff.png").ok());
    // Thresholds apply; a similarity bound of 0 accepts anything of the same size.
    EXPECT_EQ(with({"--shading", "normals", "--threshold", "ssim=0"}).exit_code, 0);
    // --update-reference replaces a reference that differs, saying so.
    const CliRun update = with({"--shading", "normals", "--update-reference"});
    EXPECT_EQ(update.exit_code, 0) << update.all();
    EXPECT_NE(update.err.find("updated the reference " + ref), std::string::npos) << update.err;
    EXPECT_EQ(with({"--shading", "normals"}).exit_code, 0);
    // The comparison options need a reference.
    EXPECT_EQ(run_facet({"render", "--size", "8x8", "-o", out, "--threshold", "diff=1"}).exit_code, 2);
    EXPECT_EQ(run_facet({"render", "--size", "8x8", "-o", out, "--update-reference"}).exit_code, 2);
}

}  // namespace

namespace {

// examples/ci/render-and-compare, the CI recipe's loop: references written on request, matches,
// a mismatch that leaves difference images and fails, and the usage error.
TEST(CiRecipe, RenderAndCompareFailsOnAChangeAndKeepsTheDifferences) {
    const fs::path dir = temp_dir();
    fs::create_directories(dir / "models");
    facet_test::write_file(dir / "models" / "a.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    facet_test::write_file(dir / "models" / "b.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n");
    const std::string script = (fs::path(facet_test::k_source_dir) / "examples/ci/render-and-compare").string();
    auto run = [&](const std::string& env, const std::string& options) {
        return facet_test::run_program("/bin/bash", {"-c", "FACET='" + facet_test::facet_binary().string() + "' " + env +
                                                               " '" + script + "' '" + (dir / "models").string() +
                                                               "' '" + (dir / "refs").string() + "' '" +
                                                               (dir / "out").string() + "' --size 32x24 " + options});
    };
    EXPECT_EQ(run("", "").exit_code, 1);  // no references yet
    const CliRun update = run("UPDATE_REFERENCES=1", "");
    EXPECT_EQ(update.exit_code, 0) << update.all();
    EXPECT_TRUE(fs::exists(dir / "refs" / "a.obj.png") && fs::exists(dir / "refs" / "b.obj.png"));
    const CliRun same = run("", "");
    EXPECT_EQ(same.exit_code, 0) << same.all();
    EXPECT_NE(same.out.find("2 of 2 models match their references"), std::string::npos) << same.out;
    const CliRun changed = run("", "--shading normals");
    EXPECT_EQ(changed.exit_code, 1) << changed.all();
    EXPECT_TRUE(fs::exists(dir / "out" / "a.obj.diff.png") && fs::exists(dir / "out" / "b.obj.diff.png"));
    EXPECT_EQ(facet_test::run_program("/bin/bash", {script}).exit_code, 2);
}

}  // namespace
