// `facet render`: one model (or the default scene) to a PNG, optionally a depth PNG and timings.
//
// The job (load, render, write) runs in a worker process (worker.hpp) unless --no-isolation: a
// file that crashes, hangs or exhausts memory inside the model reader (assimp) then ends in an
// error naming the file and the reason, exit status 1 and no output file, instead of a crash of
// facet. The worker inherits stdout and stderr, so its warnings, errors and the --benchmark line
// reach the user as they are written, and its exit status is facet's.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>

#include "facet/io.hpp"
#include "facet/primitive_counts.hpp"
#include "facet/sandbox.hpp"
#include "options.hpp"
#include "pass_files.hpp"
#include "views_output.hpp"
#include "worker.hpp"

namespace facet::cli {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The frame's colour image: width x height pixels in memory that nothing writes before the render,
// which writes them whole (an Image's vector would first clear the megabyte of a 512x512 frame:
// 0.03 ms in quiet minutes, 0.4 in busy ones, docs/BENCHMARKS.md), its rows on 64-byte lines.
class FrameImage {
public:
    FrameImage(int width, int height) {
        constexpr std::size_t line = 64;
        const std::size_t bytes = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * sizeof(Rgba8);
        // Rgba8 is an aggregate of bytes: the allocation makes its pixels (C++20's implicit objects).
        pixels_.reset(static_cast<Rgba8*>(std::aligned_alloc(line, (bytes + line - 1) / line * line)));
        if (!pixels_) throw std::bad_alloc();
    }
    Rgba8* data() const { return pixels_.get(); }

private:
    struct Free {
        void operator()(Rgba8* p) const { std::free(p); }
    };
    std::unique_ptr<Rgba8, Free> pixels_;
};

// Window depth in [0, 1] to 16 bits: round(d * 65535); the background (depth 1) is 65535.
std::vector<std::uint16_t> depth_to_u16(const std::vector<float>& depth) {
    std::vector<std::uint16_t> out(depth.size());
    for (std::size_t i = 0; i < depth.size(); ++i)
        out[i] = static_cast<std::uint16_t>(std::lround(std::clamp(depth[i], 0.0f, 1.0f) * 65535.0f));
    return out;
}

void print_benchmark(std::vector<double> frame_ms, double load_ms, std::size_t triangles, int threads, int w, int h) {
    std::sort(frame_ms.begin(), frame_ms.end());
    const std::size_t n = frame_ms.size();
    const double median = n % 2 ? frame_ms[n / 2] : (frame_ms[n / 2 - 1] + frame_ms[n / 2]) / 2;
    std::printf("{\"frames\":%zu,\"median_ms\":%.3f,\"min_ms\":%.3f,\"max_ms\":%.3f,\"load_ms\":%.3f,"
                "\"triangles\":%zu,\"threads\":%d,\"width\":%d,\"height\":%d}\n",
                n, median, frame_ms.front(), frame_ms.back(), load_ms, triangles, threads, w, h);
    std::fflush(stdout);
}

// A failed run leaves no output behind: takes back a colour image already written (only a regular
// file: -o may name a device such as /dev/null).
void remove_output(const std::string& output) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(output, ec)) std::filesystem::remove(output, ec);
}

struct RenderRequest {
    std::string model, output, depth_out;
    std::string views_folder;  // --views or --passes: the staging folder the job writes into
    int benchmark_frames = 0;  // 0: no benchmark
    RenderPlan plan;
    int threads = 0;
    bool print_config = false;  // print the settings once the model is loaded, render nothing
    WorkerLimits limits;
    bool isolated = true;
    ReferenceCheck reference;
};

void print_config(const RenderRequest& r, const Scene& scene, const Renderer& renderer) {
    ConfigText out("render");
    out.add("model", r.model.empty() ? "(the built-in default scene)" : r.model);
    out.add("output", r.output);
    if (!r.depth_out.empty()) out.add("depth-out", r.depth_out);
    if (r.benchmark_frames > 0) out.add("benchmark", std::to_string(r.benchmark_frames));
    if (!r.reference.reference.empty()) {
        out.add("reference", r.reference.reference);
        out.add("threshold", describe_thresholds(*parse_thresholds(r.reference.threshold)));
        out.add("update-reference", r.reference.update ? "on" : "off");
    }
    const Camera camera = plan_camera(scene, r.plan);
    describe_run(out, r.plan, &camera, renderer, r.limits, r.isolated);
    std::fputs(out.str().c_str(), stdout);
}

// The views and passes of the loaded scene into the staging folder (views_output.hpp), with
// progress on a terminal; returns the exit status.
int views_job(const RenderRequest& r, const Scene& scene, double load_ms) {
    const bool terminal = ::isatty(STDERR_FILENO) == 1;
    auto progress = [&](std::size_t done, std::size_t total) {
        if (terminal) std::fprintf(stderr, "\rfacet render: view %zu of %zu", done, total);
        if (terminal && done == total) std::fputc('\n', stderr);
    };
    Result<ViewsReport> done = render_views_into(scene, r.plan, r.views_folder, r.threads, progress);
    if (!done) {
        std::fprintf(stderr, "facet render: %s\n", done.error().message.c_str());
        return k_exit_failed;
    }
    if (done->stats.triangles_in > 0 && done->stats.triangles_invalid == done->stats.triangles_in) {
        std::fprintf(stderr, "facet render: %s: no valid triangles to draw\n", r.model.c_str());
        return k_exit_failed;
    }
    std::fprintf(stderr,
                 "facet render: %s: %zu %s of %s (%dx%d, %zu files, %s, load %.1f ms, render %.1f ms, "
                 "write %.1f ms)\n",
                 r.output.c_str(), done->views, done->views == 1 ? "view" : "views", to_string(r.plan.views->passes).c_str(),
                 r.plan.width, r.plan.height,
                 done->files.size(), describe_primitives(scene).c_str(), load_ms, done->render_ms, done->write_ms);
    return k_exit_ok;
}

// Load, render, write, printing its own messages; returns the exit status.
int render_job(const RenderRequest& r, const WorkerReport& report) {
    const RenderPlan& plan = r.plan;
    sandbox_test_probe();
    report.phase(WorkerPhase::loading);
    const Clock::time_point load_start = Clock::now();
    Result<Scene> scene = load_scene(r.model, plan, "facet render");
    if (!scene) {
        std::fprintf(stderr, "facet render: %s\n", scene.error().message.c_str());
        return k_exit_failed;
    }
    const double load_ms = ms_since(load_start);

    report.phase(WorkerPhase::rendering);
    if (plan.views && !r.print_config) return views_job(r, *scene, load_ms);
    const FrameImage colour(plan.width, plan.height);
    std::vector<float> depth;
    std::vector<float>* depth_ptr = r.depth_out.empty() ? nullptr : &depth;
    DrawStats stats;
    double render_ms = 0;
    int threads = 1;
    {
        // The renderer ends before the PNG is written: its thread (and its memory) go to the encoder.
        ViewRenderer renderer({.threads = r.threads});
        threads = renderer.renderer().threads();
        if (r.print_config) {
            print_config(r, *scene, renderer.renderer());
            return k_exit_ok;
        }
        const Clock::time_point render_start = Clock::now();
        const Camera camera = plan_camera(*scene, plan);
        stats = render_plan(renderer, *scene, plan, camera, colour.data(), depth_ptr);
        render_ms = ms_since(render_start);
        if (r.benchmark_frames > 0) {
            // The first frame above was the warm-up; time the next ones, each a draw and the copy of
            // the image out (the camera is framed once, as for one image: framing reads every vertex).
            std::vector<double> frames;
            for (int i = 0; i < r.benchmark_frames; ++i) {
                const Clock::time_point start = Clock::now();
                stats = render_plan(renderer, *scene, plan, camera, colour.data(), depth_ptr);
                frames.push_back(ms_since(start));
            }
            print_benchmark(frames, load_ms, scene->triangle_count(), threads, plan.width, plan.height);
        }
    }

    if (stats.triangles_in > 0 && stats.triangles_invalid == stats.triangles_in) {
        std::fprintf(stderr, "facet render: %s: no valid triangles to draw\n", r.model.c_str());
        return k_exit_failed;
    }
    report.phase(WorkerPhase::writing);
    // The files the images replace, if there are, held (O_PATH: no access asked, none checked)
    // until this process exits: their blocks are freed in its exit, after its status is reported
    // (run_in_worker), not in the rename over them (0.3-0.6 ms on ext4 for the bunny's 57 KB PNG).
    for (const std::string* replaced : {&r.output, &r.depth_out})
        if (!replaced->empty()) (void)::open(replaced->c_str(), O_PATH | O_CLOEXEC);
    // Runs only (zlib's Z_RLE), as thumbs: a render's smooth shading on a plain background deflates
    // in ~25% less time than at level 2, its file ~10% larger (docs/BENCHMARKS.md).
    if (Status s = write_png(r.output, plan.width, plan.height, colour.data(), {.threads = threads, .runs_only = true}); !s) {
        std::fprintf(stderr, "facet render: %s\n", s.error().message.c_str());
        return k_exit_failed;
    }
    if (depth_ptr) {
        report.phase(WorkerPhase::writing_depth);
        if (Status s = write_png_gray16(r.depth_out, plan.width, plan.height, depth_to_u16(depth)); !s) {
            std::fprintf(stderr, "facet render: %s\n", s.error().message.c_str());
            remove_output(r.output);
            return k_exit_failed;
        }
    }
    std::fprintf(stderr, "facet render: %s (%dx%d, %s, load %.1f ms, render %.1f ms, %d threads)\n",
                 r.output.c_str(), plan.width, plan.height, describe_primitives(*scene).c_str(), load_ms, render_ms,
                 threads);
    return k_exit_ok;
}

// After a worker that did not finish by itself: a failed run leaves no output behind, neither the
// temporaries it was writing nor a colour image it had already renamed into place.
void clean_up_after(const WorkerOutcome& outcome, const RenderRequest& r) {
    remove_temporaries(r.output);
    if (!r.depth_out.empty()) {
        remove_temporaries(r.depth_out);
        if (outcome.phase == WorkerPhase::writing_depth) remove_output(r.output);
    }
}

}  // namespace

int run_render(const std::string& model, const std::string& output, const std::string& depth_out,
               std::optional<int> benchmark_frames, const RenderOptions& options, bool camera_options_given,
               const ReferenceCheck& reference, bool output_given, bool size_given) {
    Result<RenderPlan> plan = make_plan(options, camera_options_given || !model.empty(), size_given);
    if (!plan) {
        std::fprintf(stderr, "facet render: %s\n", plan.error().message.c_str());
        return k_exit_usage;
    }
    if (plan->views) {
        const char* clash = !depth_out.empty()             ? "--depth-out (the depth pass is its exact form)"
                            : benchmark_frames                ? "--benchmark"
                            : !reference.reference.empty() ? "--reference"
                                                              : nullptr;
        if (clash) {
            std::fprintf(stderr, "facet render: --views and --passes do not go with %s\n", clash);
            return k_exit_usage;
        }
        if (!output_given && !options.print_config) {
            std::fprintf(stderr, "facet render: with --views or --passes, -o names the folder to write into\n");
            return k_exit_usage;
        }
    }
    if (benchmark_frames && *benchmark_frames < 1) {
        std::fprintf(stderr, "facet render: --benchmark must be 1 or more frames, got %d\n", *benchmark_frames);
        return k_exit_usage;
    }
    Result<WorkerLimits> limits = make_worker_limits(options, 1);
    if (!limits) {
        std::fprintf(stderr, "facet render: %s\n", limits.error().message.c_str());
        return k_exit_usage;
    }
    if (!reference_usable(reference, "facet render")) return k_exit_usage;
    // One job: the load's normals may use the threads the render will (thumbs runs one per worker).
    plan->load.threads = options.threads;
    // Views: a staging folder made here, which the worker may write into (its sandbox creates no
    // folders), moved into place when the job succeeds.
    std::optional<ViewsStaging> staging;
    if (plan->views && !options.print_config) {
        Result<ViewsStaging> staged = stage_views(output, *plan->views);
        if (!staged) {
            std::fprintf(stderr, "facet render: %s\n", staged.error().message.c_str());
            return k_exit_failed;
        }
        staging = std::move(*staged);
    }
    auto finish_views = [&](int status) {
        if (!staging) return status;
        if (status != k_exit_ok) {
            discard_views(*staging);
            return status;
        }
        if (Status s = commit_views(*staging); !s) {
            std::fprintf(stderr, "facet render: %s\n", s.error().message.c_str());
            return k_exit_failed;
        }
        return status;
    };
    const RenderRequest request{.model = model,
                                .output = output,
                                .depth_out = depth_out,
                                .views_folder = staging ? staging->folder.string() : std::string(),
                                .benchmark_frames = benchmark_frames.value_or(0),
                                .plan = *plan,
                                .threads = options.threads,
                                .print_config = options.print_config,
                                .limits = *limits,
                                .isolated = !options.no_isolation,
                                .reference = reference};
    // The reference check reads what the job wrote, after it (in this process either way).
    auto then_check = [&](int status) {
        return status == k_exit_ok && !options.print_config && !reference.reference.empty()
                   ? check_reference(output, reference)
                   : status;
    };
    keep_freed_memory_for_reuse();  // this process, or its worker, renders one file and exits
    // Only for jobs read by facet's own code (use_huge_pages_for_heap): the built-in scene, OFF and
    // STL files. Not PLY, which facet also reads itself: many PLY files (normals, colours) are left
    // to assimp, whose PLY reader reads past its buffers.
    const bool huge_pages = model.empty() || huge_pages_suit(model);
    if (options.no_isolation) {
        if (huge_pages) use_huge_pages_for_heap(limits->max_memory_bytes);
        return finish_views(then_check(render_job(request, WorkerReport{})));
    }
    std::vector<std::string> outputs{output, depth_out};
    if (staging) {  // the files go into these folders: confine_worker allows the folders of its outputs
        outputs.clear();
        for (const std::string& folder : staging->write_folders) outputs.push_back(folder + "/file");
    }

    // Nothing has started a thread yet (the Renderer is made in the worker), so forking is safe.
    const WorkerOutcome outcome = run_in_worker(
        [&](const WorkerReport& report) {
            if (huge_pages) use_huge_pages_for_heap(limits->max_memory_bytes);
            test_hooks(model);
            load_writers_for(*plan);
            confine_worker(model, outputs, plan->load.resource_dirs);
            // Here a SIGBUS from a mapped model file cut short ends the worker, which the parent
            // reports (describe_abnormal_end); in this process (--no-worker) files are read.
            RenderRequest mapped = request;
            mapped.plan.load.map_files = true;
            return render_job(mapped, report);
        },
        *limits);
    // The worker has printed its own messages for the statuses it chose, but not an exception's (run_caught
    // reports it: std::bad_alloc under --max-memory, say), which ended it with status 1 and no word.
    const std::string input = model.empty() ? "the default scene" : model;
    if (exited(outcome) && (outcome.status == k_exit_ok || outcome.status == k_exit_failed)) {
        if (outcome.status == k_exit_failed && !outcome.message.empty())
            std::fprintf(stderr, "facet render: %s: %s\n", input.c_str(), outcome.message.c_str());
        return finish_views(then_check(outcome.status));
    }
    finish_views(k_exit_failed);
    clean_up_after(outcome, request);
    std::fprintf(stderr, "facet render: %s\n", describe_abnormal_end(outcome, input, *limits).c_str());
    // Any other exit status is passed on (a sanitizer's report in a sanitizer build, say).
    return exited(outcome) && outcome.status != k_exit_ok ? outcome.status : k_exit_failed;
}

}  // namespace facet::cli
