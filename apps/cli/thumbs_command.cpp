// `facet thumbs`: many models to one PNG each, all cores busy, progress on stderr, a summary, and
// an exit code that says whether everything rendered. One broken file never stops the batch.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

#include "facet/io.hpp"
#include "options.hpp"

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

// Renders one model to its thumbnail; fills job.error on failure.
void render_job(Job& job, const RenderPlan& plan, Renderer& renderer, Framebuffer& target, Image& colour) {
    Result<Scene> scene = load_scene(job.input.string(), plan, "facet thumbs");
    if (!scene) {
        job.error = scene.error().message;
        return;
    }
    try {
        render_plan(renderer, *scene, plan, target, colour, nullptr);
    } catch (const std::exception& e) {
        job.error = job.input.string() + ": " + e.what();
        return;
    }
    if (Status s = write_png(job.output.string(), colour); !s) job.error = s.error().message;
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
    std::error_code ec;
    fs::create_directories(output_dir, ec);
    if (ec || !fs::is_directory(output_dir)) {
        std::fprintf(stderr, "facet thumbs: %s: cannot create the output directory: %s\n", output_dir.c_str(),
                     ec.message().c_str());
        return k_exit_failed;
    }

    std::vector<Job> failed;
    std::vector<Job> jobs = collect_jobs(inputs, output_dir, failed);
    Progress progress(jobs.size());
    // Files in parallel, one render thread each: loading is single-threaded, so this keeps every core busy.
    const unsigned workers = std::max(1u, std::min<unsigned>(options.threads > 0 ? options.threads
                                                                                  : std::thread::hardware_concurrency(),
                                                             static_cast<unsigned>(std::max<std::size_t>(jobs.size(), 1))));
    std::atomic<std::size_t> next{0};
    auto worker = [&] {
        Renderer renderer({.threads = 1});
        Framebuffer target(plan->width * plan->ssaa, plan->height * plan->ssaa);
        Image colour;
        for (std::size_t i; (i = next++) < jobs.size();) {
            render_job(jobs[i], *plan, renderer, target, colour);
            progress.done(jobs[i]);
        }
    };
    std::vector<std::thread> threads;
    for (unsigned t = 1; t < workers; ++t) threads.emplace_back(worker);
    worker();
    for (std::thread& t : threads) t.join();

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
