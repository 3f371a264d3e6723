// `facet thumbs`: many models to one PNG each, all cores busy, progress on stderr, a summary, and
// an exit code that says whether everything rendered. One broken file never stops the batch.
// Collections (README, "Collections"): the objects may come from a manifest (collection.hpp), be
// cut into shards, be logged as they finish (results_log.hpp) and be resumed from that log; a
// manifest entry with views or passes gets a folder of files instead (views_output.hpp).
//
// Each file is loaded, rendered and written in a worker process (worker.hpp), up to --threads at a
// time, while this process only schedules them, shows progress, logs and collects results; a worker
// serves the following files of its folder, or of the run (--worker-sharing batch: run_jobs). A file that makes a reader hang, crash or
// allocate without bound (assimp cannot be interrupted, and a crash in it would take every other
// file with it) then costs only its own worker: past --timeout seconds the worker is killed and the
// file reported as "gave up after N s"; a crash is reported with its signal. The worker writes its thumbnail atomically (a temporary file
// renamed into place) before this process logs it, so a log line always stands for a finished
// file; the temporary of a killed worker is removed here, and those of a killed run by the next
// one. This process is single-threaded, so forking is safe, and each worker draws with one thread.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <unordered_set>

#include "collection.hpp"
#include "options.hpp"
#include "results_log.hpp"
#include "thumbnail_job.hpp"
#include "views_output.hpp"
#include "worker.hpp"

namespace facet::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// One object of the run and what became of it.
struct Job {
    ObjectEntry entry;  // entry.reason set: failed before rendering (a bad entry, a missing input)
    std::optional<std::pair<int, int>> size;  // the entry's own options, checked
    std::optional<UpAxis> up_axis;
    std::optional<ViewsPlan> views;  // the entry's views or passes: a folder of files
    std::string options_hash;
    bool done_before = false;  // --resume: the log has it with these options and its outputs exist
    // The outcome.
    FailReason reason = FailReason::none;
    std::string error;
    ThumbnailFigures figures;
    double total_ms = 0;

    std::vector<std::string> written;  // with views: the folder's files, once it is in place

    // What the object writes into the output directory: the thumbnail <stem>.png, or with views
    // the folder <stem>.
    std::string output_name() const { return views ? entry.stem : entry.stem + ".png"; }
    // Its files, relative to the output directory: the thumbnail, or the folder's files (known once
    // written: the rig and the passes decide them).
    std::vector<std::string> outputs() const { return views ? written : std::vector<std::string>{output_name()}; }
};

// A name for the thumbnail that keeps the model's relative path and extension, so "a/b.obj" and
// "a_b.obj" or "b.stl" cannot meet; what still collides gets -2, -3, ... in sorted order. The
// name without ".png" is the object's id.
std::string flat_name(const fs::path& relative) {
    std::string name;
    for (const auto& part : relative) {
        if (!name.empty()) name += "__";
        name += part.string();
    }
    return name;
}

// Expands the command line's inputs: files as given, directories recursively (model files only),
// sorted per input. An input that does not exist is an entry that failed.
std::vector<ObjectEntry> collect_inputs(const std::vector<std::string>& inputs) {
    std::vector<ObjectEntry> entries;
    std::map<std::string, int> used;
    auto add = [&](const fs::path& input, const fs::path& relative) {
        std::string name = flat_name(relative);
        if (int n = ++used[name]; n > 1) name.append("-").append(std::to_string(n));
        ObjectEntry& e = entries.emplace_back();
        e.id = e.stem = name;
        e.path = e.origin = input.string();
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
            ObjectEntry& e = entries.emplace_back();
            e.id = e.path = e.origin = in;
            e.reason = FailReason::missing;
            e.error = in + ": no such file or directory";
        }
    }
    return entries;
}

// The options hash of an object (collection.hpp's options_hash) from --print-config's text of its plan.
std::string options_hash(const RenderPlan& plan, const ObjectOptions& options, const Renderer& renderer,
                         const WorkerLimits& limits) {
    ConfigText config("thumbs");
    describe_run(config, plan, nullptr, renderer, limits, true);
    return options_hash(config.str(), options);
}

RenderPlan object_plan(const RenderPlan& plan, const Job& job) {
    RenderPlan p = plan;
    if (job.size) std::tie(p.width, p.height) = *job.size;
    if (job.up_axis) p.load.up_axis = *job.up_axis;
    p.views = job.views;
    return p;
}

// Checks an entry's own options into the job; a bad one fails the job as a bad entry. `options`
// are the command line's, which a rig's views start from.
void check_object_options(Job& job, const RenderPlan& plan, const RenderOptions& options) {
    const ObjectOptions& o = job.entry.options;
    std::string problem;
    if (o.size) {
        if (Result<std::pair<int, int>> size = parse_image_size("size", *o.size, plan.ssaa, true)) job.size = *size;
        else problem = size.error().message;
    }
    if (problem.empty() && o.up_axis) {
        if (*o.up_axis == "y" || *o.up_axis == "z") job.up_axis = *o.up_axis == "z" ? UpAxis::z : UpAxis::y;
        else problem = "up_axis must be \"y\" or \"z\", got '" + *o.up_axis + "'";
    }
    if (problem.empty() && (o.views || !o.passes.empty())) {
        // As facet render --views ... --passes ... would read them.
        RenderOptions with_views = options;
        with_views.views = o.views;
        with_views.passes.reset();
        for (const std::string& pass : o.passes) with_views.passes = with_views.passes ? *with_views.passes + "," + pass : pass;
        RenderPlan p = object_plan(plan, job);
        if (Status s = make_views_plan(with_views, job.size.has_value(), p); !s) {
            problem = s.error().message;
            if (problem.rfind("--views: ", 0) == 0 || problem.rfind("--passes: ", 0) == 0) problem.erase(0, 2);  // the keys' names
        } else {
            job.views = std::move(p.views);
            if (!job.size && (p.width != plan.width || p.height != plan.height)) job.size = {p.width, p.height};
        }
    }
    if (!problem.empty()) {
        job.entry.reason = FailReason::bad_entry;
        job.entry.error = job.entry.origin + ": " + problem;
    }
}

class Progress {
public:
    explicit Progress(std::size_t total) : total_(total), tty_(isatty(STDERR_FILENO)) {}
    void done(const Job& job, const fs::path& output) {
        std::lock_guard lock(mutex_);
        ++finished_;
        failed_ += job.error.empty() ? 0 : 1;
        if (!tty_) {
            if (job.error.empty())
                std::fprintf(stderr, "facet thumbs: [%zu/%zu] %s -> %s\n", finished_, total_, job.entry.path.c_str(),
                             output.c_str());
            else
                std::fprintf(stderr, "facet thumbs: [%zu/%zu] FAILED %s\n", finished_, total_, job.error.c_str());
            return;
        }
        constexpr int k_bar = 30;
        const int filled = static_cast<int>(k_bar * finished_ / std::max<std::size_t>(total_, 1));
        std::fprintf(stderr, "\r[%.*s%*s] %zu/%zu  %zu failed  %-40.40s", filled, "==============================",
                     k_bar - filled, "", finished_, total_, failed_, fs::path(job.entry.path).filename().c_str());
        if (finished_ == total_) std::fprintf(stderr, "\n");
        std::fflush(stderr);
    }

private:
    std::mutex mutex_;
    std::size_t total_, finished_ = 0, failed_ = 0;
    bool tty_;
};

// How a worker that did not finish its job by itself ended, as a reason.
FailReason reason_for_abnormal_end(const WorkerOutcome& outcome) {
    switch (outcome.end) {
    case WorkerOutcome::End::timed_out: return FailReason::timed_out;
    case WorkerOutcome::End::signalled: return FailReason::crashed;
    case WorkerOutcome::End::exited:
    case WorkerOutcome::End::not_started: break;
    }
    return FailReason::failed;
}

// Appends jobs' lines to the log, if there is one; a log that cannot be written is said once.
class ResultsLog {
public:
    explicit ResultsLog(std::optional<LogWriter> writer) : writer_(std::move(writer)) {}
    bool enabled() const { return writer_.has_value(); }
    void add(const Job& job) {
        if (!writer_) return;
        LogRecord r;
        r.id = job.entry.id;
        r.path = job.entry.path;
        r.line = job.entry.line;
        r.reason = job.reason;
        r.error = job.error;
        r.triangles = job.figures.triangles;
        r.load_ms = job.figures.load_ms;
        r.render_ms = job.figures.render_ms;
        r.write_ms = job.figures.write_ms;
        r.total_ms = job.total_ms;
        if (job.reason == FailReason::none) r.outputs = job.outputs();
        r.options_hash = job.options_hash;
        if (Status s = writer_->append(format_log_line(r)); !s && !failed_) {
            std::fprintf(stderr, "facet thumbs: %s\n", s.error().message.c_str());
            failed_ = true;
        }
    }
    bool failed() const { return failed_; }

private:
    std::optional<LogWriter> writer_;
    bool failed_ = false;
};

// How many objects a worker serves at most before a fresh one takes over: a fork, an exit and
// the first touches of a fresh heap (~3 ms an object) shared by many, while what one object leaves
// behind (the heap's growth, its fragments) cannot build up for long.
constexpr std::size_t k_objects_per_worker = 16;

// The objects that one worker may serve in a row share a key, and with it one sandbox (the output
// folder is the same for all; the rules name the folders models are read from): thumbnails (not
// views, whose staging folders are each object's own) of regular files (not links, whose target may
// lie elsewhere). By folder, the key is the model's folder. Across folders (--worker-sharing
// batch), it is a batch of the next `batch` such objects of `order`, and `batch_folders` gets each
// batch's folders, all of which its workers may read. An empty key: a worker of its own.
std::vector<std::string> sharing_keys(const std::vector<Job>& jobs, const std::vector<std::size_t>& order,
                                      bool across_folders, std::size_t batch,
                                      std::map<std::string, std::vector<std::string>>& batch_folders) {
    std::vector<std::string> keys(jobs.size());
    std::size_t shared = 0;
    for (const std::size_t i : order) {
        std::error_code ec;
        const Job& job = jobs[i];
        if (job.views || fs::symlink_status(job.entry.path, ec).type() != fs::file_type::regular) continue;
        std::string folder = fs::path(job.entry.path).parent_path().string();
        if (folder.empty()) folder = ".";
        if (!across_folders) {
            keys[i] = std::move(folder);
            continue;
        }
        keys[i] = "batch " + std::to_string(shared++ / batch);
        std::vector<std::string>& folders = batch_folders[keys[i]];
        if (std::find(folders.begin(), folders.end(), folder) == folders.end()) folders.push_back(std::move(folder));
    }
    return keys;
}

// Runs the jobs in `order` in worker processes, at most `workers` at a time, each within `limits`,
// reporting each finished job to `progress` and the log. A worker serves the following jobs of the
// same sharing key as long as they come; a job that crashes or runs out of memory in a worker that
// served others before, or that assimp has to read there (k_exit_fresh_worker), is run again in a
// fresh one, so that each object's result is what a process of its own gives. Returns false when a
// worker ended abnormally after its jobs (a sanitizer's report at exit).
bool run_jobs(std::vector<Job>& jobs, const std::vector<std::size_t>& order, const RenderPlan& plan,
              const fs::path& out_dir, unsigned workers, bool across_folders, const WorkerLimits& limits,
              Progress& progress, ResultsLog& log) {
    std::vector<Worker> running;
    std::vector<Clock::time_point> started(jobs.size());
    std::vector<std::optional<ViewsStaging>> staged(jobs.size());  // of the jobs with views
    // A batch is as many objects as the workers serve before fresh ones take over.
    std::map<std::string, std::vector<std::string>> batch_folders;
    const std::vector<std::string> keys =
        sharing_keys(jobs, order, across_folders, k_objects_per_worker * workers, batch_folders);
    std::vector<std::size_t> again;  // jobs to run again, each first in a fresh worker
    std::size_t next = 0;
    bool workers_ok = true;
    auto output_of = [&](std::size_t i) { return out_dir / jobs[i].output_name(); };
    auto finish = [&](std::size_t i, FailReason reason, std::string error) {
        Job& job = jobs[i];
        if (staged[i] && reason == FailReason::none) {
            // The folder's files, then the folder in place of any earlier one (whose files a
            // smaller rig would leave standing).
            for (const auto& e : fs::recursive_directory_iterator(staged[i]->folder))
                if (e.is_regular_file())
                    job.written.push_back(job.entry.stem + "/" + e.path().lexically_relative(staged[i]->folder).string());
            std::sort(job.written.begin(), job.written.end());
            std::error_code ec;
            fs::remove_all(output_of(i), ec);
            if (Status s = commit_views(*staged[i]); !s) {
                job.written.clear();
                reason = FailReason::write_failed;
                error = s.error().message;
            }
        } else if (staged[i]) {
            discard_views(*staged[i]);
        }
        job.reason = reason;
        job.error = error;
        job.total_ms = ms_since(started[i]);
        progress.done(job, output_of(i));
        log.add(job);
    };
    // Stages a job's folder (views) and stamps its start; false if it failed already.
    auto prepare = [&](std::size_t i) {
        started[i] = Clock::now();
        if (jobs[i].views && !staged[i]) {
            Result<ViewsStaging> s = stage_views(output_of(i).string(), *jobs[i].views);
            if (!s) {
                finish(i, FailReason::write_failed, s.error().message);
                return false;
            }
            staged[i] = std::move(*s);
        }
        return true;
    };
    // In the worker: the job the parent sent. `confined` and `huge_heap` are the worker's own
    // copies (a fork's).
    bool confined = false, huge_heap = false;
    const ServingJob serve = [&](std::size_t i, const WorkerReport& report, bool& go_on) {
        if (!confined) keep_freed_memory_for_reuse();  // a worker reuses what its jobs free
        // The heap in huge pages, as facet render's: from the first job when its file suits, else
        // from its render on (below), since assimp reads no file in a worker after its first load.
        if (!huge_heap && (confined || huge_pages_suit(jobs[i].entry.path))) {
            use_huge_pages_for_heap(limits.max_memory_bytes);
            huge_heap = true;
        }
        ThumbnailJob job{jobs[i].entry.path, object_plan(plan, jobs[i]), output_of(i), staged[i] ? &*staged[i] : nullptr};
        // Else from the first job's render: once its file is loaded, assimp reads no more.
        if (!huge_heap) {
            job.huge_heap_after_load = limits.max_memory_bytes;
            huge_heap = true;
        }
        job.confine = !confined;
        job.fresh_process = !confined;
        if (const auto b = batch_folders.find(keys[i]); b != batch_folders.end()) job.other_model_dirs = b->second;
        confined = true;
        const std::size_t assimp_imports = assimp_import_count();
        const int status = run_thumbnail_job(job, report);
        // After assimp read a file (only a fresh process's first job may give it one), the process
        // ends: the next objects get a fresh one too.
        go_on = !(job.fresh_process && assimp_import_count() != assimp_imports) && !jobs[i].views;
        return status;
    };
    while (next < order.size() || !again.empty() || !running.empty()) {
        // Idle workers: the next job if it shares their key, or retire. (A worker that died idle
        // fails the send: wait_for_jobs then reports the job as its worker's end.)
        for (Worker& w : running) {
            if (w.busy || w.job_fd < 0) continue;
            if (next < order.size() && w.served < k_objects_per_worker && !keys[w.tag].empty() &&
                keys[order[next]] == keys[w.tag] && prepare(order[next]))
                send_job(w, order[next++], limits);
            else
                retire(w);
        }
        std::size_t alive = 0;
        for (const Worker& w : running) alive += w.job_fd >= 0 || w.busy ? 1 : 0;
        while (alive < workers && (next < order.size() || !again.empty())) {
            std::size_t i;
            if (!again.empty()) {
                i = again.back();
                again.pop_back();
            } else {
                i = order[next++];
            }
            if (!prepare(i)) continue;
            WorkerOutcome failed;
            std::optional<Worker> w = start_serving_worker(serve, limits, running, failed);
            if (!w) {
                finish(i, FailReason::failed, describe_abnormal_end(failed, jobs[i].entry.path, limits));
                continue;
            }
            send_job(*w, i, limits);
            running.push_back(std::move(*w));
            ++alive;
        }
        for (JobEnd& end : wait_for_jobs(running)) {
            const std::size_t i = end.tag;
            const WorkerOutcome& outcome = end.outcome;
            Job& job = jobs[i];
            if (end.after_job) {
                std::fprintf(stderr, "facet thumbs: the worker process that rendered %s ended abnormally after it: %s\n",
                             job.entry.path.c_str(), describe_abnormal_end(outcome, job.entry.path, limits).c_str());
                workers_ok = false;
                continue;
            }
            job.figures = ThumbnailFigures::parse(outcome.figures);
            const bool after_others = end.served_before > 0;
            if (exited(outcome) && outcome.status == k_exit_ok) {
                finish(i, FailReason::none, {});
            } else if (exited(outcome) && outcome.status == k_exit_fresh_worker && after_others) {
                again.push_back(i);
            } else if (exited(outcome) && outcome.status == k_exit_failed && !outcome.message.empty()) {
                const FailReason reason = job.figures.reason == FailReason::none ? FailReason::failed : job.figures.reason;
                if (reason == FailReason::out_of_memory && after_others) again.push_back(i);
                else finish(i, reason, outcome.message);
            } else {
                if (!staged[i]) remove_temporaries(output_of(i));  // of a worker killed while writing
                if (outcome.end == WorkerOutcome::End::signalled && after_others) again.push_back(i);
                else finish(i, reason_for_abnormal_end(outcome), describe_abnormal_end(outcome, job.entry.path, limits));
            }
        }
    }
    return workers_ok;
}

// The end of the run on stderr: the counts, the speed, and the failures grouped by reason (all of
// them, or without a log the first few of each reason when there are many).
void print_summary(const std::vector<Job>& jobs, std::size_t attempted, std::size_t rendered, std::size_t skipped,
                   double seconds, bool logged) {
    std::map<FailReason, std::vector<const Job*>> failures;
    for (const Job& j : jobs)
        if (j.reason != FailReason::none) failures[j.reason].push_back(&j);
    std::size_t failed = 0;
    for (const auto& [reason, list] : failures) failed += list.size();
    std::fprintf(stderr, "facet thumbs: %zu rendered, %zu failed", rendered, failed);
    if (skipped > 0) std::fprintf(stderr, ", %zu skipped (done before)", skipped);
    if (attempted > 0) std::fprintf(stderr, " in %.1f s (%.1f objects/s)", seconds, static_cast<double>(attempted) / seconds);
    std::fprintf(stderr, "\n");
    constexpr std::size_t k_listed_with_log = 10;
    for (const auto& [reason, list] : failures) {
        std::fprintf(stderr, "  %s: %zu\n", reason_label(reason), list.size());
        const std::size_t shown = logged ? std::min(list.size(), k_listed_with_log) : list.size();
        for (std::size_t i = 0; i < shown; ++i) std::fprintf(stderr, "    failed: %s\n", list[i]->error.c_str());
        if (shown < list.size()) std::fprintf(stderr, "    ... and %zu more (all in the log)\n", list.size() - shown);
    }
}

// Removes the temporaries of our outputs that a killed run left (one pass over the folder): files
// NAME.png.tmpN, and the staging folders NAME.tmpN of objects with views.
void remove_stale_temporaries(const fs::path& out_dir, const std::vector<Job>& jobs) {
    std::unordered_set<std::string> outputs;
    for (const Job& j : jobs)
        if (j.entry.reason == FailReason::none) outputs.insert(j.output_name());
    remove_temporaries(out_dir, outputs);
}

// --resume: marks the jobs whose latest "ok" line has the same options hash and the same outputs,
// all of them present (with views, the files that line lists, all in the object's folder: the rig
// and the passes, which the hash covers, decide them); a job logged before with anything else loses
// its old outputs first, so that a run killed before its new line cannot leave them standing for
// the old one.
void mark_done_before(std::vector<Job>& jobs, const LogContents& log, const fs::path& out_dir) {
    for (Job& job : jobs) {
        if (job.entry.reason != FailReason::none) continue;
        const auto it = log.finished.find(job.entry.id);
        if (it == log.finished.end()) continue;
        const std::vector<std::string>& logged = it->second.outputs;
        const std::vector<std::string> outputs = job.views ? logged : job.outputs();
        const std::string folder = job.entry.stem + "/";
        const bool named = job.views ? !logged.empty() && std::all_of(logged.begin(), logged.end(), [&](const std::string& o) {
            return o.size() > folder.size() && o.compare(0, folder.size(), folder) == 0;
        })
                                     : logged == outputs;
        std::error_code ec;
        const bool present = std::all_of(outputs.begin(), outputs.end(), [&](const std::string& o) {
            return fs::is_regular_file(out_dir / o, ec) && fs::file_size(out_dir / o, ec) > 0;
        });
        job.done_before = named && present && it->second.options_hash == job.options_hash;
        if (!job.done_before && job.views) fs::remove_all(out_dir / job.output_name(), ec);
        else if (!job.done_before) fs::remove(out_dir / job.output_name(), ec);
    }
}

}  // namespace

int run_thumbs(const std::vector<std::string>& inputs, const std::string& output_dir, const RenderOptions& options,
               const CollectionOptions& collection) {
    const char* command = "facet thumbs";
    RenderOptions o = options;
    // --size N means N x N; checked as given first, so that a bad one is quoted as the user wrote it.
    if (Result<std::pair<int, int>> size = parse_image_size("--size", o.size, 1, /*square=*/true); !size) {
        std::fprintf(stderr, "%s: %s\n", command, size.error().message.c_str());
        return k_exit_usage;
    }
    if (o.size.find('x') == std::string::npos) o.size += "x" + o.size;
    Result<RenderPlan> plan = make_plan(o, /*camera_options_given=*/true);  // models are always framed
    if (!plan) {
        std::fprintf(stderr, "%s: %s\n", command, plan.error().message.c_str());
        return k_exit_usage;
    }
    if (collection.manifest.empty() == inputs.empty()) {
        std::fprintf(stderr, "%s: give model files and directories, or --manifest, not both\n", command);
        return k_exit_usage;
    }
    if (collection.resume && collection.log.empty()) {
        std::fprintf(stderr, "%s: --resume needs --log, the log it resumes from\n", command);
        return k_exit_usage;
    }
    Shard shard;
    if (!collection.shard.empty()) {
        Result<Shard> s = parse_shard(collection.shard);
        if (!s) {
            std::fprintf(stderr, "%s: %s\n", command, s.error().message.c_str());
            return k_exit_usage;
        }
        shard = *s;
    }

    std::optional<std::vector<ManifestLine>> only;
    if (!collection.manifest_lines.empty()) {
        Result<std::vector<ManifestLine>> lines = parse_manifest_lines(collection.manifest_lines);
        if (!lines || collection.manifest.empty()) {
            std::fprintf(stderr, "%s: %s\n", command,
                         lines ? "--manifest-lines needs --manifest" : lines.error().message.c_str());
            return k_exit_usage;
        }
        only = std::move(*lines);
    }
    std::vector<ObjectEntry> entries;
    if (!collection.manifest.empty()) {
        Result<std::vector<ObjectEntry>> read = read_manifest(collection.manifest, shard, only ? &*only : nullptr);
        if (!read) {
            std::fprintf(stderr, "%s: %s\n", command, read.error().message.c_str());
            return k_exit_usage;
        }
        entries = std::move(*read);
    } else {
        std::vector<ObjectEntry> found = collect_inputs(inputs);
        if (found.empty()) {
            std::fprintf(stderr, "%s: no model files found in the inputs\n", command);
            return k_exit_failed;
        }
        for (ObjectEntry& e : found)
            if (shard_of(e.id, shard.count) == shard.index) entries.push_back(std::move(e));
    }
    // Files in parallel, one process each drawing with one thread: loading is single-threaded, so
    // this keeps every core busy.
    const auto cores = static_cast<unsigned>(resolve_threads(options.threads));
    const unsigned workers = std::max(1u, static_cast<unsigned>(std::min<std::size_t>(cores, entries.size())));
    Result<WorkerLimits> limits = make_worker_limits(options, workers);
    if (!limits) {
        std::fprintf(stderr, "%s: %s\n", command, limits.error().message.c_str());
        return k_exit_usage;
    }
    const Renderer renderer({.threads = k_thumbnail_threads});  // as each worker's (starts no thread)
    const bool across_folders = collection.worker_sharing.empty() ? !collection.manifest.empty()
                                                                  : collection.worker_sharing == "batch";

    std::vector<Job> jobs;
    jobs.reserve(entries.size());
    std::map<std::string, std::string> hashes;  // by the object's own options: few distinct ones
    for (ObjectEntry& e : entries) {
        Job& job = jobs.emplace_back();
        job.entry = std::move(e);
        if (job.entry.reason != FailReason::none) continue;
        check_object_options(job, *plan, o);
        if (job.entry.reason != FailReason::none) continue;
        const ObjectOptions& oo = job.entry.options;
        std::string key = oo.size.value_or("") + "|" + oo.up_axis.value_or("") + "|" + oo.views.value_or("") + "|";
        for (const std::string& p : oo.passes) key += p + ",";
        auto [it, inserted] = hashes.try_emplace(key);
        if (inserted) it->second = options_hash(object_plan(*plan, job), oo, renderer, *limits);
        job.options_hash = it->second;
    }

    if (options.print_config) {
        ConfigText out("thumbs");
        out.add("inputs", std::to_string(jobs.size()) + (collection.manifest.empty() ? " model files" : " objects"));
        out.add("output", output_dir);
        if (!collection.manifest.empty()) out.add("manifest", collection.manifest);
        out.add("shard", std::to_string(shard.index) + "/" + std::to_string(shard.count));
        out.add("log", collection.log.empty() ? "none" : collection.log);
        out.add("resume", collection.resume ? "yes" : "no");
        out.add("workers", std::to_string(workers));
        out.add("worker-sharing", across_folders ? "batch" : "folder");
        describe_run(out, *plan, nullptr, renderer, *limits, true);
        std::fputs(out.str().c_str(), stdout);
        return k_exit_ok;
    }
    std::error_code ec;
    fs::create_directories(output_dir, ec);
    if (ec || !fs::is_directory(output_dir)) {
        std::fprintf(stderr, "%s: %s: cannot create the output directory: %s\n", command, output_dir.c_str(),
                     ec.message().c_str());
        return k_exit_failed;
    }
    std::optional<LogWriter> writer;
    if (!collection.log.empty()) {
        if (collection.resume) {
            Result<LogContents> previous = read_log(collection.log);
            if (!previous) {
                std::fprintf(stderr, "%s: %s\n", command, previous.error().message.c_str());
                return k_exit_failed;
            }
            mark_done_before(jobs, *previous, output_dir);
            if (previous->unreadable > 0)
                std::fprintf(stderr, "%s: warning: %s: %zu lines are not log records and were skipped\n", command,
                             collection.log.c_str(), previous->unreadable);
        }
        Result<LogWriter> opened = LogWriter::open(collection.log);
        if (!opened) {
            std::fprintf(stderr, "%s: %s\n", command, opened.error().message.c_str());
            return k_exit_failed;
        }
        writer.emplace(std::move(*opened));
    }
    ResultsLog log(std::move(writer));
    // A scan of the whole output folder: once per run, but not once per task of a few objects
    // (--manifest-lines), whose caller does it once for all of them.
    if (!only) remove_stale_temporaries(output_dir, jobs);

    // Bad entries are finished already: logged first, then the rest rendered in order.
    std::vector<std::size_t> order;
    std::size_t skipped = 0;
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        Job& job = jobs[i];
        if (job.entry.reason != FailReason::none) {
            job.reason = job.entry.reason;
            job.error = job.entry.error;
            log.add(job);
        } else if (job.done_before) {
            ++skipped;
        } else {
            order.push_back(i);
        }
    }
    if (skipped > 0)
        std::fprintf(stderr, "%s: resuming: %zu of %zu objects done before (%s), %zu to render\n", command, skipped,
                     jobs.size(), collection.log.c_str(), order.size());

    const Clock::time_point start = Clock::now();
    // The readers' module opened once here, before the workers are forked, when an object needs it
    // (each worker would otherwise open and relocate it again).
    if (std::any_of(order.begin(), order.end(), [&](std::size_t i) { return !has_own_parser(jobs[i].entry.path); }))
        (void)open_model_reader_module();
    Progress progress(order.size());
    const bool workers_ok = run_jobs(jobs, order, *plan, output_dir, workers, across_folders, *limits, progress, log);
    const double seconds = ms_since(start) / 1000;

    const std::size_t rendered = static_cast<std::size_t>(std::count_if(
        order.begin(), order.end(), [&](std::size_t i) { return jobs[i].reason == FailReason::none; }));
    print_summary(jobs, order.size(), rendered, skipped, seconds, log.enabled());
    const bool all_good = std::none_of(jobs.begin(), jobs.end(), [](const Job& j) { return j.reason != FailReason::none; });
    return all_good && workers_ok && !log.failed() ? k_exit_ok : k_exit_failed;
}

}  // namespace facet::cli
