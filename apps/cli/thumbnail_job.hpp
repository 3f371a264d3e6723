// facet command line: one thumbnail, the per-object job of `facet thumbs` and `facet thumbnail`.
// In: a model path, a plan and an output path, inside a worker process (worker.hpp); out: the PNG,
// written atomically, or with views the files of a staged folder (views_output.hpp), and the job's
// figures and error through the worker's report. It confines the worker first (thumbs' sandbox);
// scheduling, naming, staging, logs and progress stay with the commands.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "collection.hpp"
#include "options.hpp"
#include "views_output.hpp"
#include "worker.hpp"

namespace facet::cli {

// The renderer's threads in a thumbnail worker: loading is single-threaded, so thumbs keeps every
// core busy with one process per file, and one small image is not worth starting threads for.
constexpr int k_thumbnail_threads = 1;

// Milliseconds since `start`: the figures' unit.
double ms_since(std::chrono::steady_clock::time_point start);

// What a thumbnail job measured, sent to the parent as text (WorkerReport::figures).
struct ThumbnailFigures {
    std::optional<std::size_t> triangles;
    std::optional<double> load_ms, render_ms, write_ms;
    FailReason reason = FailReason::none;

    std::string text() const;
    static ThumbnailFigures parse(const std::string& text);
};

struct ThumbnailJob {
    std::string model;
    RenderPlan plan;
    std::filesystem::path output;  // the PNG; unused with views
    // With plan.views: the staged folder the views and passes go into (made by the parent: the
    // sandbox creates no folders).
    const ViewsStaging* staging = nullptr;
    const char* command = "facet thumbs";  // prefixes the model's warnings on stderr
    // Fail a model that leaves the image blank (every pixel the same: no triangle, or none valid
    // and with an area) instead of writing it: a file manager shows its own icon then.
    bool refuse_empty = false;
    // In a worker that serves several objects (thumbs): confine only for the first (the sandbox is
    // the same for the others, and its layers stack), and give back, unread by assimp, an object
    // that is not the first and that assimp has to read (k_exit_fresh_worker: the parent gives it
    // to a fresh worker).
    bool confine = true;
    bool fresh_process = true;
    // With confine: the folders of the other objects the worker may serve (--worker-sharing batch),
    // which its sandbox lets it read too. Each model's own resources stay confined to its folder.
    std::vector<std::string> other_model_dirs{};
    // Set: once the model is loaded, the heap is advised for huge pages (use_huge_pages_for_heap
    // with this memory cap) for the render's buffers, also when the load ran out of memory (the
    // worker's next jobs use that heap). For a thumbs worker's first job that assimp may read: its
    // reads past a buffer are over by then, and they still meet the plain heap.
    std::optional<std::uint64_t> huge_heap_after_load{};
};

// The status of a job given back to be run in a fresh worker process (ThumbnailJob::fresh_process).
constexpr int k_exit_fresh_worker = 3;

// The worker's side: confine, load, render, write, timing each; returns the worker's exit status
// (k_exit_ok only when the PNG, or every file of the views, is in place).
int run_thumbnail_job(const ThumbnailJob& job, const WorkerReport& report);

}  // namespace facet::cli
