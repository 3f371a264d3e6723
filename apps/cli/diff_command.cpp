// `facet diff A.png B.png` and `facet render --reference REF.png`: two images compared by the
// library's compare_images (facet/compare.hpp) against thresholds, one summary line (or JSON), a
// difference picture on request or on a failed reference check. Exit codes: 0 within the
// thresholds, 1 not, 2 a usage or file error.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "facet/io.hpp"
#include "json.hpp"
#include "options.hpp"

namespace facet::cli {
namespace {

Error usage(const std::string& message) { return Error{ErrorCode::invalid_argument, message}; }

bool parse_number(const std::string& text, double& out) {
    char* end = nullptr;
    out = std::strtod(text.c_str(), &end);
    return !text.empty() && *end == '\0' && std::isfinite(out);
}

std::string fixed(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

std::string size_of(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

// read_png of a folder fails in zlib ("not a valid PNG file (stream error)"): say what was given instead.
Result<Image> read_png_file(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        return Result<Image>(Error{ErrorCode::io, path + ": is a directory, not a PNG file"});
    return read_png(path);
}

std::string json_number(double v, const char* format) { return std::isfinite(v) ? fixed(format, v) : "null"; }

}  // namespace

Result<CompareThresholds> parse_thresholds(const std::string& spec) {
    CompareThresholds t;
    if (spec.empty()) return t;
    bool pixel_bound = false, similarity_bound = false;
    std::stringstream in(spec);
    std::string item;
    const std::string form = "--threshold takes diff=N,pixels=N or P%,ssim=S,psnr=DB (any of them), got '" + spec + "'";
    while (std::getline(in, item, ',')) {
        const std::size_t eq = item.find('=');
        if (eq == std::string::npos) return usage(form);
        const std::string key = item.substr(0, eq);
        std::string value = item.substr(eq + 1);
        const bool percent = !value.empty() && value.back() == '%';
        if (percent) value.pop_back();
        double v = 0;
        if (!parse_number(value, v) || v < 0 || (percent && key != "pixels")) return usage(form);
        if (key == "diff") {
            if (v > 255 || v != std::floor(v)) return usage("--threshold diff must be a whole number 0..255, got '" + value + "'");
            t.tolerance = static_cast<int>(v);
            pixel_bound = true;
        } else if (key == "pixels") {
            if (percent) {
                if (v > 100) return usage("--threshold pixels must be at most 100%");
                t.max_differing_fraction = v / 100;
            } else {
                if (v != std::floor(v)) return usage("--threshold pixels must be a whole number or a percentage");
                t.max_differing_pixels = static_cast<std::size_t>(v);
            }
            pixel_bound = true;
        } else if (key == "ssim") {
            if (v > 1) return usage("--threshold ssim must be 0..1, got '" + value + "'");
            t.min_ssim = v;
            similarity_bound = true;
        } else if (key == "psnr") {
            t.min_psnr = v;
            similarity_bound = true;
        } else {
            return usage(form);
        }
    }
    // Bounds on similarity alone are for images from other renderers: every edge differs a little.
    t.check_pixels = pixel_bound || !similarity_bound;
    return t;
}

std::string describe_thresholds(const CompareThresholds& t) {
    std::string out;
    auto add = [&](const std::string& s) { out += (out.empty() ? "" : ",") + s; };
    if (t.check_pixels) {
        add("diff=" + std::to_string(t.tolerance));
        add("pixels=" + (t.max_differing_fraction ? fixed("%g", *t.max_differing_fraction * 100) + "%"
                                                  : std::to_string(t.max_differing_pixels)));
    }
    if (t.min_ssim) add("ssim=" + fixed("%g", *t.min_ssim));
    if (t.min_psnr) add("psnr=" + fixed("%g", *t.min_psnr));
    return out;
}

std::string comparison_summary(const std::string& a, const std::string& b, const ImageComparison& c, bool pass,
                               const std::string& why) {
    std::string s = a + " vs " + b + ": ";
    if (!c.same_size()) return s + "sizes differ (" + size_of(c.width_a, c.height_a) + " and " + size_of(c.width_b, c.height_b) + "): MISMATCH";
    const auto& d = c.max_difference;
    s += size_of(c.width_a, c.height_a) + ", " + std::to_string(c.differing_pixels) + " of " + std::to_string(c.pixels) +
         " pixels differ by more than " + std::to_string(c.tolerance) + " (largest difference R " + std::to_string(d[0]) +
         " G " + std::to_string(d[1]) + " B " + std::to_string(d[2]) + " A " + std::to_string(d[3]) + "), PSNR " +
         (std::isfinite(c.psnr) ? fixed("%.2f", c.psnr) + " dB" : std::string("inf")) + ", SSIM " + fixed("%.6f", c.ssim);
    return s + (pass ? ": match" : ": MISMATCH (" + why + ")");
}

std::string diff_image_path(const std::string& output) {
    std::filesystem::path p(output);
    const std::string stem = p.extension() == ".png" ? p.stem().string() : p.filename().string();
    return (p.parent_path() / (stem + ".diff.png")).string();
}

int run_diff(const std::string& path_a, const std::string& path_b, const DiffOptions& options) {
    Result<CompareThresholds> thresholds = parse_thresholds(options.threshold);
    if (!thresholds) {
        std::fprintf(stderr, "facet diff: %s\n", thresholds.error().message.c_str());
        return k_exit_usage;
    }
    Result<Image> a = read_png_file(path_a);
    Result<Image> b = a ? read_png_file(path_b) : Result<Image>(a.error());
    if (!a || !b) {
        std::fprintf(stderr, "facet diff: %s\n", (a ? b : a).error().message.c_str());
        return k_exit_usage;
    }
    const ImageComparison c = compare_images(*a, *b, thresholds->tolerance);
    std::string why;
    const bool pass = within_thresholds(c, *thresholds, &why);
    std::string diff_note;
    if (!options.diff_image.empty()) {
        if (!c.same_size()) {
            diff_note = "no difference image: the sizes differ";
        } else if (Status s = write_png(options.diff_image, difference_image(*a, *b, c.tolerance)); !s) {
            std::fprintf(stderr, "facet diff: %s\n", s.error().message.c_str());
            return k_exit_usage;
        }
    }
    if (options.json) {
        const auto& d = c.max_difference;
        std::printf("{\"a\":%s,\"b\":%s,\"width_a\":%d,\"height_a\":%d,\"width_b\":%d,\"height_b\":%d,\"same_size\":%s,",
                    json::quote(path_a).c_str(), json::quote(path_b).c_str(), c.width_a, c.height_a, c.width_b,
                    c.height_b, c.same_size() ? "true" : "false");
        if (c.same_size())
            std::printf("\"pixels\":%zu,\"differing_pixels\":%zu,\"tolerance\":%d,\"max_difference\":[%d,%d,%d,%d],"
                        "\"psnr\":%s,\"ssim\":%s,",
                        c.pixels, c.differing_pixels, c.tolerance, d[0], d[1], d[2], d[3],
                        json_number(c.psnr, "%.4f").c_str(), json_number(c.ssim, "%.8f").c_str());
        std::printf("\"thresholds\":%s,\"pass\":%s,\"reason\":%s}\n", json::quote(describe_thresholds(*thresholds)).c_str(),
                    pass ? "true" : "false", json::quote(why).c_str());
    } else {
        std::printf("facet diff: %s\n", comparison_summary(path_a, path_b, c, pass, why).c_str());
    }
    if (!diff_note.empty()) std::fprintf(stderr, "facet diff: %s\n", diff_note.c_str());
    return pass ? k_exit_ok : k_exit_failed;
}

bool reference_usable(const ReferenceCheck& r, const char* command) {
    if (r.reference.empty()) {
        if (!r.threshold.empty() || r.update) {
            std::fprintf(stderr, "%s: --threshold and --update-reference need --reference\n", command);
            return false;
        }
        return true;
    }
    if (Result<CompareThresholds> t = parse_thresholds(r.threshold); !t) {
        std::fprintf(stderr, "%s: %s\n", command, t.error().message.c_str());
        return false;
    }
    std::error_code ec;
    if (std::filesystem::is_directory(r.reference, ec)) {  // it was found out after rendering
        std::fprintf(stderr, "%s: the reference %s is a directory, not a PNG file\n", command, r.reference.c_str());
        return false;
    }
    if (!r.update && !std::filesystem::exists(r.reference, ec)) {
        std::fprintf(stderr, "%s: the reference %s does not exist (--update-reference writes it)\n", command,
                     r.reference.c_str());
        return false;
    }
    return true;
}

int check_reference(const std::string& output, const ReferenceCheck& r) {
    const char* command = "facet render";
    Result<Image> rendered = read_png(output);
    if (!rendered) {
        std::fprintf(stderr, "%s: %s\n", command, rendered.error().message.c_str());
        return k_exit_failed;
    }
    std::error_code ec;
    const bool exists = std::filesystem::exists(r.reference, ec);
    Result<Image> reference = exists ? read_png_file(r.reference) : Result<Image>(Error{ErrorCode::io, ""});
    if (exists && !reference && !r.update) {
        std::fprintf(stderr, "%s: %s\n", command, reference.error().message.c_str());
        return k_exit_usage;
    }
    const CompareThresholds thresholds = *parse_thresholds(r.threshold);  // checked by reference_usable
    if (reference) {
        const ImageComparison c = compare_images(*rendered, *reference, thresholds.tolerance);
        std::string why;
        const bool pass = within_thresholds(c, thresholds, &why);
        const std::string summary = comparison_summary(output, r.reference, c, pass, why);
        if (pass) {
            std::fprintf(stderr, "%s: %s\n", command, summary.c_str());
            return k_exit_ok;
        }
        if (!r.update) {
            std::string note;
            if (c.same_size()) {
                const std::string diff = diff_image_path(output);
                const Status s = write_png(diff, difference_image(*rendered, *reference, c.tolerance));
                note = s ? "; where they differ: " + diff : "; " + s.error().message;
            }
            std::fprintf(stderr, "%s: %s%s\n", command, summary.c_str(), note.c_str());
            return k_exit_failed;
        }
        std::fprintf(stderr, "%s: %s\n", command, summary.c_str());
    }
    if (Status s = write_png(r.reference, *rendered); !s) {
        std::fprintf(stderr, "%s: %s\n", command, s.error().message.c_str());
        return k_exit_failed;
    }
    std::fprintf(stderr, "%s: %s the reference %s from %s\n", command, exists ? "updated" : "wrote", r.reference.c_str(),
                 output.c_str());
    return k_exit_ok;
}

}  // namespace facet::cli
