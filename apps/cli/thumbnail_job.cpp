// facet command line: one thumbnail in a worker process (thumbnail_job.hpp): confine, load,
// render, write the PNG atomically (or the views and passes into a staged folder). Shared by `facet thumbs` and `facet thumbnail`.
#include "thumbnail_job.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "facet/io.hpp"
#include "facet/model.hpp"
#include "facet/sandbox.hpp"
#include "pass_files.hpp"

namespace facet::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

FailReason reason_for_load_error(const Error& e, const std::string& path) {
    switch (e.code) {
    case ErrorCode::io: {
        std::error_code ec;
        return fs::exists(path, ec) ? FailReason::unreadable : FailReason::missing;
    }
    case ErrorCode::bad_format:
    case ErrorCode::invalid_argument: return FailReason::bad_file;
    case ErrorCode::unsupported: return FailReason::unsupported;
    case ErrorCode::limit_exceeded: return FailReason::too_large;
    }
    return FailReason::failed;
}

}  // namespace

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

std::string ThumbnailFigures::text() const {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%lld %.3f %.3f %.3f %d", triangles ? static_cast<long long>(*triangles) : -1LL,
                  load_ms.value_or(-1), render_ms.value_or(-1), write_ms.value_or(-1), static_cast<int>(reason));
    return buf;
}

ThumbnailFigures ThumbnailFigures::parse(const std::string& text) {
    ThumbnailFigures f;
    long long t = -1;
    double l = -1, r = -1, w = -1;
    int reason = 0;
    if (std::sscanf(text.c_str(), "%lld %lf %lf %lf %d", &t, &l, &r, &w, &reason) != 5) return f;
    if (t >= 0) f.triangles = static_cast<std::size_t>(t);
    if (l >= 0) f.load_ms = l;
    if (r >= 0) f.render_ms = r;
    if (w >= 0) f.write_ms = w;
    if (reason >= 0 && reason <= static_cast<int>(FailReason::failed)) f.reason = static_cast<FailReason>(reason);
    return f;
}

int run_thumbnail_job(const ThumbnailJob& job, const WorkerReport& report) {
    test_hooks(job.model);
    const RenderPlan& plan = job.plan;
    std::vector<std::string> outputs{job.output.string()};
    if (job.staging) {  // confine_worker allows the folders of its outputs
        outputs.clear();
        for (const std::string& folder : job.staging->write_folders) outputs.push_back(folder + "/file");
    }
    load_writers_for(plan);
    if (job.confine) {
        confine_worker(job.model, outputs, plan.load.resource_dirs, job.other_model_dirs);
        sandbox_test_probe();
    }
    ThumbnailFigures f;
    std::string error;
    bool huge_heap_advised = false;
    try {
        Image colour;
        report.phase(WorkerPhase::loading);
        Clock::time_point start = Clock::now();
        const std::size_t assimp_imports = assimp_import_count();
        allow_assimp_imports(job.fresh_process);
        Result<Scene> scene = load_scene(job.model, plan, job.command);
        f.load_ms = ms_since(start);
        if (!job.fresh_process && assimp_import_count() != assimp_imports) return k_exit_fresh_worker;
        if (job.huge_heap_after_load) {
            use_huge_pages_for_heap(*job.huge_heap_after_load);
            huge_heap_advised = true;
        }
        if (!scene) {
            error = scene.error().message;
            f.reason = reason_for_load_error(scene.error(), job.model);
        } else {
            f.triangles = scene->triangle_count();
            report.phase(WorkerPhase::rendering);
            start = Clock::now();
            try {
                if (job.staging) {  // the views and passes, written as they are rendered
                    Result<ViewsReport> views =
                        render_views_into(*scene, plan, job.staging->folder.string(), k_thumbnail_threads);
                    if (views) {
                        f.render_ms = views->render_ms;
                        f.write_ms = views->write_ms;
                    } else {
                        error = views.error().message;
                        f.reason = views.error().code == ErrorCode::io ? FailReason::write_failed : FailReason::render_failed;
                    }
                } else {  // one thumbnail; render_views_into has a ViewRenderer of its own
                    ViewRenderer renderer({.threads = k_thumbnail_threads});
                    render_plan(renderer, *scene, plan, plan_camera(*scene, plan), colour, nullptr);
                }
                const auto& px = colour.pixels;
                if (!job.staging && job.refuse_empty &&
                    std::all_of(px.begin(), px.end(), [&](Rgba8 p) { return p == px.front(); })) {
                    error = job.model + ": nothing to draw (" + std::to_string(scene->triangle_count()) +
                            " triangles, none visible)";
                    f.reason = FailReason::bad_file;
                }
            } catch (const std::bad_alloc&) {
                throw;
            } catch (const std::exception& e) {
                error = job.model + ": " + e.what();
                f.reason = FailReason::render_failed;
            }
            if (!f.render_ms) f.render_ms = ms_since(start);
        }
        if (error.empty() && !job.staging) {
            report.phase(WorkerPhase::writing);
            start = Clock::now();
            if (Status s = write_png(job.output.string(), colour, {.threads = k_thumbnail_threads, .runs_only = true}); !s) {
                error = s.error().message;
                f.reason = FailReason::write_failed;
            }
            f.write_ms = ms_since(start);
        }
    } catch (const std::bad_alloc&) {
        error = job.model + ": out of memory";
        f.reason = FailReason::out_of_memory;
        // A load that ran out of memory still advises the heap: a thumbs worker goes on to its next
        // jobs, which would otherwise never have it (its first job was the one to advise it).
        if (job.huge_heap_after_load && !huge_heap_advised) use_huge_pages_for_heap(*job.huge_heap_after_load);
    }
    report.figures(f.text());
    if (error.empty()) return k_exit_ok;
    report.error(error);
    return k_exit_failed;
}

}  // namespace facet::cli
