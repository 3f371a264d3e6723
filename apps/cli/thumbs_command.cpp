// `facet thumbs`: many models to one PNG each, all cores busy, progress on stderr, a summary, and
// an exit code that says whether everything rendered. One broken file never stops the batch.
//
// Each file is loaded, rendered and written by a worker process of its own (worker.hpp), up to
// --threads at a time, while this process only schedules them, shows progress and collects results.
// A file that makes a reader hang, crash or allocate without bound (assimp cannot be interrupted,
// and a crash in it would take every other file with it) then costs only its own worker: past
// --timeout seconds the worker is killed and the file reported as "gave up after N s"; a crash is
// reported with its signal. The worker writes its thumbnail atomically (a temporary file renamed
// into place); the temporary of a killed worker is removed here, so an abandoned file leaves
// nothing behind. This process is single-threaded, so forking is safe, and each worker draws with
// one thread.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>

#include "facet/io.hpp"
#include "options.hpp"
#include "worker.hpp"

namespace facet::cli {
namespace {

namespace fs = std::filesystem;

struct Job {
    fs::path input;
    fs::path output;
    std::string error;  // empty: rendered
};

// A name for the thumbnail that keeps the model's relative path and extension, so "a/b.obj" and
// "a_b.obj" or "b.stl" cannot meet; what still collides gets -2, -3, ... in sorted order.
std::string flat_name(const fs::path& relative) {
    std::string name;
    for (const auto& part : relative) {
        if (!name.empty()) name += "__";
        name += part.string();
    }
    return name + ".png";
}

// Expands the inputs: files as given, directories recursively (model files only), sorted per input.
std::vector<Job> collect_jobs(const std::vector<std::string>& inputs, const fs::path& out_dir, std::vector<Job>& failed) {
    std::vector<Job> jobs;
    std::map<std::string, int> used;
    auto add = [&](const fs::path& input, const fs::path& relative) {
        std::string name = flat_name(relative);
        if (int n = ++used[name]; n > 1) name = name.substr(0, name.size() - 4) + "-" + std::to_string(n) + ".png";
        jobs.push_back({input, out_dir / name, {}});
    };
    for (const std::string& in : inputs) {
        std::error_code ec;
        const fs::path path(in);
        if (fs::is_directory(path, ec)) {
            std::vector<fs::path> found;
            for (auto it = fs::recursive_directory_iterator(path, fs::directory_options::skip_permission_denied, ec);
                 !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
                if (it->is_regular_file(ec) && is_supported_model_file(it->path().string())) found.push_back(it->path());
            std::sort(found.begin(), found.end());
            for (const fs::path& f : found) add(f, fs::relative(f, path, ec));
        } else if (fs::exists(path, ec)) {
            add(path, path.filename());
        } else {
            failed.push_back({path, {}, in + ": no such file or directory"});
        }
    }
    return jobs;
}

class Progress {
public:
    explicit Progress(std::size_t total) : total_(total), tty_(isatty(STDERR_FILENO)) {}
    void done(const Job& job) {
        std::lock_guard lock(mutex_);
        ++finished_;
        failed_ += job.error.empty() ? 0 : 1;
        if (!tty_) {
            if (job.error.empty())
                std::fprintf(stderr, "facet thumbs: [%zu/%zu] %s -> %s\n", finished_, total_, job.input.c_str(),
                             job.output.c_str());
            else
                std::fprintf(stderr, "facet thumbs: [%zu/%zu] FAILED %s\n", finished_, total_, job.error.c_str());
            return;
        }
        constexpr int k_bar = 30;
        const int filled = static_cast<int>(k_bar * finished_ / std::max<std::size_t>(total_, 1));
        std::fprintf(stderr, "\r[%.*s%*s] %zu/%zu  %zu failed  %-40.40s", filled, "==============================",
                     k_bar - filled, "", finished_, total_, failed_, job.input.filename().c_str());
        if (finished_ == total_) std::fprintf(stderr, "\n");
        std::fflush(stderr);
    }

private:
    std::mutex mutex_;
    std::size_t total_, finished_ = 0, failed_ = 0;
    bool tty_;
};

// Each worker's renderer: loading is single-threaded, so one process per file keeps every core busy.
constexpr int k_worker_threads = 1;

// Renders one model to its thumbnail; fills job.error on failure.
void render_job(Job& job, const RenderPlan& plan, Renderer& renderer, Framebuffer& target, Image& colour,
                const WorkerReport& report) {
    report.phase(WorkerPhase::loading);
    Result<Scene> scene = load_scene(job.input.string(), plan, "facet thumbs");
    if (!scene) {
        job.error = scene.error().message;
        return;
    }
    report.phase(WorkerPhase::rendering);
    try {
        render_plan(renderer, *scene, plan, plan_camera(*scene, plan), target, colour, nullptr);
    } catch (const std::exception& e) {
        job.error = job.input.string() + ": " + e.what();
        return;
    }
    report.phase(WorkerPhase::writing);
    if (Status s = write_png(job.output.string(), colour); !s) job.error = s.error().message;
}

// The worker's side: load, render, write; an error goes to the parent through the report.
int thumbnail_job(Job job, const RenderPlan& plan, const WorkerReport& report) {
    test_hook_sleep(job.input.string());
    Renderer renderer({.threads = k_worker_threads});
    Framebuffer target(plan.width * plan.ssaa, plan.height * plan.ssaa);
    Image colour;
    render_job(job, plan, renderer, target, colour, report);
    if (job.error.empty()) return k_exit_ok;
    report.error(job.error);
    return k_exit_failed;
}

// Runs every job in worker processes, at most `workers` at a time, each within `limits`,
// reporting each finished job to `progress`.
void run_jobs(std::vector<Job>& jobs, const RenderPlan& plan, unsigned workers, const WorkerLimits& limits,
              Progress& progress) {
    std::vector<Worker> running;
    std::size_t next = 0;
    auto finish = [&](std::size_t i, const std::string& error) {
        jobs[i].error = error;
        progress.done(jobs[i]);
    };
    while (next < jobs.size() || !running.empty()) {
        while (running.size() < workers && next < jobs.size()) {
            const std::size_t i = next++;
            WorkerOutcome failed;
            std::optional<Worker> w = start_worker(
                [&, i](const WorkerReport& report) { return thumbnail_job(jobs[i], plan, report); }, limits, running, failed);
            if (!w) {
                finish(i, describe_abnormal_end(failed, jobs[i].input.string(), limits));
                continue;
            }
            w->tag = i;
            running.push_back(std::move(*w));
        }
        for (auto& [w, outcome] : wait_for_workers(running)) {
            const Job& job = jobs[w.tag];
            if (exited(outcome) && outcome.status == k_exit_ok) {
                finish(w.tag, {});
            } else if (exited(outcome) && outcome.status == k_exit_failed && !outcome.message.empty()) {
                finish(w.tag, outcome.message);
            } else {
                remove_temporaries(job.output);  // of a worker killed while writing
                finish(w.tag, describe_abnormal_end(outcome, job.input.string(), limits));
            }
        }
    }
}

}  // namespace

int run_thumbs(const std::vector<std::string>& inputs, const std::string& output_dir, const RenderOptions& options) {
    RenderOptions o = options;
    if (o.size.find('x') == std::string::npos) o.size += "x" + o.size;  // --size N means N x N
    Result<RenderPlan> plan = make_plan(o, /*camera_options_given=*/true);  // models are always framed
    if (!plan) {
        std::fprintf(stderr, "facet thumbs: %s\n", plan.error().message.c_str());
        return k_exit_usage;
    }
    std::vector<Job> failed;
    std::vector<Job> jobs = collect_jobs(inputs, output_dir, failed);
    // Files in parallel, one process each drawing with one thread: loading is single-threaded, so
    // this keeps every core busy.
    const auto cores = static_cast<unsigned>(resolve_threads(options.threads));
    const unsigned workers = std::max(1u, static_cast<unsigned>(std::min<std::size_t>(cores, jobs.size())));
    Result<WorkerLimits> limits = make_worker_limits(options, workers);
    if (!limits) {
        std::fprintf(stderr, "facet thumbs: %s\n", limits.error().message.c_str());
        return k_exit_usage;
    }
    if (options.print_config) {
        ConfigText out("thumbs");
        out.add("inputs", std::to_string(jobs.size()) + " model files");
        out.add("output", output_dir);
        out.add("workers", std::to_string(workers));
        const Renderer renderer({.threads = k_worker_threads});  // as each worker's (starts no thread)
        describe_run(out, *plan, nullptr, renderer, *limits, true);
        std::fputs(out.str().c_str(), stdout);
        return k_exit_ok;
    }
    std::error_code ec;
    fs::create_directories(output_dir, ec);
    if (ec || !fs::is_directory(output_dir)) {
        std::fprintf(stderr, "facet thumbs: %s: cannot create the output directory: %s\n", output_dir.c_str(),
                     ec.message().c_str());
        return k_exit_failed;
    }

    Progress progress(jobs.size());
    run_jobs(jobs, *plan, workers, *limits, progress);

    const std::size_t rendered =
        static_cast<std::size_t>(std::count_if(jobs.begin(), jobs.end(), [](const Job& j) { return j.error.empty(); }));
    for (const Job& j : jobs)
        if (!j.error.empty()) failed.push_back(j);
    std::fprintf(stderr, "facet thumbs: %zu rendered, %zu failed\n", rendered, failed.size());
    for (const Job& j : failed) std::fprintf(stderr, "  failed: %s\n", j.error.c_str());
    if (jobs.empty() && failed.empty()) {
        std::fprintf(stderr, "facet thumbs: no model files found in the inputs\n");
        return k_exit_failed;
    }
    return failed.empty() ? k_exit_ok : k_exit_failed;
}

}  // namespace facet::cli
