// `facet thumbs`: many models to one PNG each, all cores busy, progress on stderr, a summary, and
// an exit code that says whether everything rendered. One broken file never stops the batch.
//
// Each file is loaded, rendered and written by a child process of its own (fork), up to one per
// worker at a time, while this process only schedules them, shows progress and collects results.
// A file that makes a reader hang or crash (assimp cannot be interrupted, and a crash in it would
// take every other file with it) then costs only its own child: past --timeout seconds the child
// is killed and the file reported as "timed out after N s"; a crash is reported with its signal.
// The child writes its thumbnail atomically (a temporary file renamed into place); the temporary
// of a killed child is removed here, so an abandoned file leaves nothing behind.
// The parent is single-threaded, so forking is safe, and each child draws with one thread.
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
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

// TEST HOOK, for the tests of --timeout only: when FACET_TEST_SLEEP_ON is set to a non-empty
// string, a child whose input path contains it sleeps instead of working, as a file that hangs a
// reader would. No file can make assimp hang on purpose, so the tests need this to exercise the
// timeout; without the variable (as always outside the tests) it does nothing.
void test_hook_sleep(const Job& job) {
    const char* pattern = std::getenv("FACET_TEST_SLEEP_ON");
    if (pattern && *pattern && job.input.string().find(pattern) != std::string::npos)
        for (;;) pause();  // until the parent kills this child
}

// The child's side: load, render, write, report any error through `fd`, exit. _exit, not exit:
// the child owns none of the parent's buffers or atexit work.
[[noreturn]] void run_child(Job& job, const RenderPlan& plan, int fd) {
    int status = 1;
    try {
        test_hook_sleep(job);
        Renderer renderer({.threads = 1});
        Framebuffer target(plan.width * plan.ssaa, plan.height * plan.ssaa);
        Image colour;
        render_job(job, plan, renderer, target, colour);
        status = job.error.empty() ? 0 : 1;
    } catch (const std::exception& e) {
        job.error = job.input.string() + ": " + e.what();
    } catch (...) {
        job.error = job.input.string() + ": failed with an unknown exception";
    }
    for (std::size_t done = 0; done < job.error.size();) {
        const ssize_t n = write(fd, job.error.data() + done, job.error.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        done += static_cast<std::size_t>(n);
    }
    std::fflush(stderr);
    _exit(status);
}

using Clock = std::chrono::steady_clock;

struct Child {
    pid_t pid = -1;
    int fd = -1;          // read end of the pipe the child reports its error through
    std::size_t job = 0;
    Clock::time_point deadline;
    std::string message;  // what the child has written so far
};

std::string seconds_text(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", s);
    return buf;
}

// The temporary files write_file_atomic makes for `output` ("<name>.tmp<n>"), left by a killed child.
void remove_temporaries(const fs::path& output) {
    const std::string prefix = output.filename().string() + ".tmp";
    std::error_code ec;
    for (fs::directory_iterator it(output.parent_path(), ec), end; !ec && it != end; it.increment(ec))
        if (it->path().filename().string().rfind(prefix, 0) == 0) fs::remove(it->path(), ec);
}

// Runs every job in child processes, at most `workers` at a time, each within `timeout` seconds
// (0: no limit), reporting each finished job to `progress`.
void run_jobs(std::vector<Job>& jobs, const RenderPlan& plan, unsigned workers, double timeout, Progress& progress) {
    std::vector<Child> running;
    std::size_t next = 0;
    auto finish = [&](Child& c, const std::string& error) {
        jobs[c.job].error = error;
        progress.done(jobs[c.job]);
    };
    while (next < jobs.size() || !running.empty()) {
        while (running.size() < workers && next < jobs.size()) {
            Child c;
            c.job = next++;
            int fds[2];
            if (pipe(fds) != 0) {
                finish(c, jobs[c.job].input.string() + ": cannot start a worker process: " + std::strerror(errno));
                continue;
            }
            std::fflush(stderr);
            c.pid = fork();
            if (c.pid == 0) {
                close(fds[0]);
                for (const Child& other : running) close(other.fd);
                run_child(jobs[c.job], plan, fds[1]);
            }
            close(fds[1]);
            if (c.pid < 0) {
                close(fds[0]);
                finish(c, jobs[c.job].input.string() + ": cannot start a worker process: " + std::strerror(errno));
                continue;
            }
            c.fd = fds[0];
            c.deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout));
            running.push_back(std::move(c));
        }
        if (running.empty()) continue;

        int wait_ms = -1;
        if (timeout > 0) {
            Clock::time_point first = running.front().deadline;
            for (const Child& c : running) first = std::min(first, c.deadline);
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(first - Clock::now()).count();
            wait_ms = static_cast<int>(std::clamp<long long>(left + 1, 0, 60'000));
        }
        std::vector<pollfd> polled;
        for (const Child& c : running) polled.push_back({c.fd, POLLIN, 0});
        if (poll(polled.data(), polled.size(), wait_ms) < 0 && errno != EINTR) {
            std::fprintf(stderr, "facet thumbs: poll failed: %s\n", std::strerror(errno));
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }

        const Clock::time_point now = Clock::now();
        for (std::size_t i = 0; i < running.size();) {
            Child& c = running[i];
            bool ended = false;
            if (i < polled.size() && polled[i].revents != 0) {
                char buf[4096];
                const ssize_t n = read(c.fd, buf, sizeof buf);
                if (n > 0) c.message.append(buf, static_cast<std::size_t>(n));
                ended = n == 0 || (n < 0 && errno != EINTR && errno != EAGAIN);
            }
            if (ended) {
                // The pipe is closed: the child is exiting (or has exited).
                int status = 0;
                while (waitpid(c.pid, &status, 0) < 0 && errno == EINTR) {}
                const std::string& input = jobs[c.job].input.string();
                std::string error;
                if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
                    error.clear();
                } else if (WIFEXITED(status) && WEXITSTATUS(status) == 1 && !c.message.empty()) {
                    error = c.message;
                } else if (WIFSIGNALED(status)) {
                    error = input + ": the worker process crashed (signal " + std::to_string(WTERMSIG(status)) + ", " +
                            strsignal(WTERMSIG(status)) + ")";
                    remove_temporaries(jobs[c.job].output);
                } else {
                    error = input + ": the worker process failed (exit status " + std::to_string(WEXITSTATUS(status)) + ")" +
                            (c.message.empty() ? "" : ": " + c.message);
                }
                close(c.fd);
                finish(c, error);
            } else if (timeout > 0 && now >= c.deadline) {
                kill(c.pid, SIGKILL);
                while (waitpid(c.pid, nullptr, 0) < 0 && errno == EINTR) {}
                close(c.fd);
                remove_temporaries(jobs[c.job].output);
                finish(c, jobs[c.job].input.string() + ": timed out after " + seconds_text(timeout) +
                              " s (abandoned; --timeout sets the limit)");
                ended = true;
            }
            if (ended) {
                running.erase(running.begin() + static_cast<std::ptrdiff_t>(i));
                polled.erase(polled.begin() + static_cast<std::ptrdiff_t>(i));
            } else {
                ++i;
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
    if (!(options.timeout >= 0 && std::isfinite(options.timeout))) {
        std::fprintf(stderr, "facet thumbs: --timeout must be 0 (no limit) or a number of seconds\n");
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
    // Files in parallel, one process each drawing with one thread: loading is single-threaded, so
    // this keeps every core busy.
    const unsigned workers = std::max(1u, std::min<unsigned>(options.threads > 0 ? options.threads
                                                                                  : std::thread::hardware_concurrency(),
                                                             static_cast<unsigned>(std::max<std::size_t>(jobs.size(), 1))));
    run_jobs(jobs, *plan, workers, options.timeout, progress);

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
