// `facet thumbnail [-s SIZE] INPUT OUTPUT`: one model to one thumbnail for a file manager, as the
// freedesktop thumbnailer entry (packaging/facet.thumbnailer) calls it. In: a path or a file:// URI;
// out: a PNG of SIZE x SIZE with a transparent background, written atomically. The job is
// thumbs' (thumbnail_job.hpp): one worker process, its sandbox and limits. Exit 0 only when the PNG
// is in place; on any failure no PNG, an error on stderr and exit 1 (2: a bad command line).
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <string>

#include "options.hpp"
#include "thumbnail_job.hpp"
#include "worker.hpp"

namespace facet::cli {
namespace {

const char* const k_command = "facet thumbnail";

Error usage(const std::string& message) { return Error{ErrorCode::invalid_argument, message}; }

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// Whether `text` is a URI: "file:" (any case), or a scheme followed by "//" (RFC 3986: a letter,
// then letters, digits, '+', '-', '.'). A path such as "part:2.stl" stays a path.
bool is_uri(const std::string& text, std::string& scheme) {
    const std::size_t colon = text.find(':');
    if (colon == std::string::npos || colon == 0 || !std::isalpha(static_cast<unsigned char>(text[0]))) return false;
    scheme = text.substr(0, colon);
    for (char& c : scheme) {
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '+' && c != '-' && c != '.') return false;
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    return scheme == "file" || text.compare(colon + 1, 2, "//") == 0;
}

// INPUT as file managers pass it: a local path as is, or a file:// URI (file:///a%20b.stl,
// file://localhost/..., file:/...) percent-decoded as GLib's g_filename_from_uri does: an encoded
// '/' or NUL, a query or a fragment are refused, as are other hosts and other schemes (facet reads
// local files only).
Result<std::string> local_path(const std::string& input) {
    std::string scheme;
    if (!is_uri(input, scheme)) return input;
    if (scheme != "file")
        return usage("'" + input + "': " + scheme + ": URIs are not read; give a local path or a file:// URI");
    std::string rest = input.substr(scheme.size() + 1);
    if (rest.compare(0, 2, "//") == 0) {
        const std::size_t slash = rest.find('/', 2);
        const std::string host = rest.substr(2, slash == std::string::npos ? std::string::npos : slash - 2);
        if (host != "" && host != "localhost")
            return usage("'" + input + "': the file is on another host ('" + host + "'); facet reads local files only");
        rest = slash == std::string::npos ? "" : rest.substr(slash);
    }
    if (rest.empty() || rest[0] != '/') return usage("'" + input + "': a file URI needs an absolute path");
    if (rest.find_first_of("?#") != std::string::npos)
        return usage("'" + input + "': a file URI with a query or a fragment names no file");
    std::string path;
    for (std::size_t i = 0; i < rest.size(); ++i) {
        if (rest[i] != '%') {
            path += rest[i];
            continue;
        }
        const int hi = i + 2 < rest.size() ? hex_digit(rest[i + 1]) : -1;
        const int lo = hi >= 0 ? hex_digit(rest[i + 2]) : -1;
        if (lo < 0) return usage("'" + input + "': '%' must be followed by two hexadecimal digits");
        const char c = static_cast<char>(hi * 16 + lo);
        if (c == '\0' || c == '/') return usage("'" + input + "': an encoded '/' or NUL is not part of a file name");
        path += c;
        i += 2;
    }
    return path;
}

}  // namespace

RenderOptions thumbnailer_options() {
    RenderOptions o = thumbnail_options();
    o.background = "transparent";
    return o;
}

int run_thumbnail(const std::string& input, const std::string& output, int size, const RenderOptions& options) {
    Result<std::string> model = local_path(input);
    if (!model) {
        std::fprintf(stderr, "%s: %s\n", k_command, model.error().message.c_str());
        return k_exit_usage;
    }
    if (size < 1) {
        std::fprintf(stderr, "%s: -s must be 1 or more pixels, got %d\n", k_command, size);
        return k_exit_usage;
    }
    RenderOptions o = options;
    o.size = size_text(size, size);
    Result<RenderPlan> plan = make_plan(o, /*camera_options_given=*/true);  // the model is framed
    if (!plan) {
        std::fprintf(stderr, "%s: %s\n", k_command, plan.error().message.c_str());
        return k_exit_usage;
    }
    Result<WorkerLimits> limits = make_worker_limits(o, 1);
    if (!limits) {
        std::fprintf(stderr, "%s: %s\n", k_command, limits.error().message.c_str());
        return k_exit_usage;
    }
    if (options.print_config) {
        ConfigText out("thumbnail");
        out.add("model", *model);
        out.add("output", output);
        describe_run(out, *plan, nullptr, Renderer({.threads = k_thumbnail_threads}), *limits, true);
        std::fputs(out.str().c_str(), stdout);
        return k_exit_ok;
    }

    keep_freed_memory_for_reuse();  // the worker renders one file and exits
    const ThumbnailJob job{.model = *model, .plan = *plan, .output = output, .command = k_command, .refuse_empty = true};
    // The heap advised for huge pages from the start for the files facet's own code reads (OFF,
    // STL), as facet render's and a thumbs worker's. Not once another file is loaded, as a thumbs
    // worker's first job has it: for one job that gained nothing (docs/RELIABILITY.md, session 16).
    const bool huge_pages = huge_pages_suit(*model);
    const WorkerOutcome outcome = run_in_worker(
        [&](const WorkerReport& report) {
            if (huge_pages) use_huge_pages_for_heap(limits->max_memory_bytes);
            return run_thumbnail_job(job, report);
        },
        *limits);
    if (exited(outcome) && outcome.status == k_exit_ok) return k_exit_ok;
    if (exited(outcome) && outcome.status == k_exit_failed && !outcome.message.empty()) {
        std::fprintf(stderr, "%s: %s\n", k_command, outcome.message.c_str());
        return k_exit_failed;
    }
    // Killed or crashed: no temporary left behind, nor a PNG renamed into place just before.
    remove_temporaries(output);
    std::error_code ec;
    if (outcome.phase == WorkerPhase::writing && std::filesystem::is_regular_file(output, ec))
        std::filesystem::remove(output, ec);
    std::fprintf(stderr, "%s: %s\n", k_command, describe_abnormal_end(outcome, *model, *limits).c_str());
    return k_exit_failed;
}

}  // namespace facet::cli
