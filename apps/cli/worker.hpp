// facet command line: jobs (load a model, render, write) in worker processes: one job each, or
// several jobs one after another (a serving worker).
//
// assimp cannot be interrupted, and some damaged files make it crash, hang or allocate without
// bound (docs/RELIABILITY.md lists them). A job in a forked worker costs only itself when that
// happens: the parent sees the worker die of a signal, kills it past its deadline, and caps its
// memory, then reports the file with the reason. `facet render` runs its one job this way and
// `facet thumbs` many at once; both go through the functions below.
//
// Fork only while the process has one thread (before any Renderer exists): a forked child gets
// only the forking thread, and locks held by the others would stay locked forever.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <sys/types.h>
#include <unordered_set>
#include <vector>

namespace facet::cli {

// What a worker is doing. It tells the parent as it goes, so that a crash can be blamed on the
// model reader (loading) or on facet (rendering, writing), and so that a worker killed after it
// renamed its colour image into place can have that image taken back.
enum class WorkerPhase : char {
    starting = 's',
    loading = 'l',
    rendering = 'r',
    writing = 'w',
    writing_depth = 'd',  // the colour image is in place, the depth image is being written
};

struct WorkerLimits {
    double timeout_seconds = 0;          // the whole job; 0: no limit
    std::uint64_t max_memory_bytes = 0;  // the worker's RLIMIT_DATA; 0: no limit
};

// Whether this process's orphans are reaped: true in the initial PID namespace, whose init reaps
// them as its work; false in a container's, where PID 1 may be any program that never waits
// (`docker run image python gen.py`) and each worker left to it would stay a zombie. A one-job
// worker lets facet return before its own exit only when this holds.
bool orphans_are_reaped();

// Whether --max-memory can be applied: not in sanitizer builds, whose shadow memory alone is
// terabytes of writable mappings that RLIMIT_DATA counts (every allocation would fail).
bool memory_cap_supported();

// The default memory cap: three quarters of the physical memory (facet/defaults.hpp), so that a file that makes the
// reader allocate without bound fails alone instead of pushing the machine into swap or the OOM
// killer. 0 when it cannot be determined.
std::uint64_t default_max_memory_bytes();

// The worker's end of its report pipe. In-process runs (--no-isolation) use one without a pipe,
// whose reports go nowhere.
class WorkerReport {
public:
    explicit WorkerReport(int fd = -1) : fd_(fd) {}
    void phase(WorkerPhase p) const;
    // The job's error message (thumbs: the parent prints it in its summary). Last in the report.
    void error(const std::string& message) const;
    // Figures about the job for the parent (thumbs: triangles and times for its log), as text
    // without control characters; before error().
    void figures(const std::string& text) const;

private:
    int fd_;
};

// Runs in the worker; returns its exit status.
using WorkerJob = std::function<int(const WorkerReport&)>;

struct WorkerOutcome {
    enum class End { exited, signalled, timed_out, not_started };
    End end = End::not_started;
    int status = 0;  // exited: the exit status; signalled: the signal
    WorkerPhase phase = WorkerPhase::starting;
    std::string message;  // exited: the error the job reported; not_started: why
    std::string figures;  // what the job sent with WorkerReport::figures, if anything
};

using WorkerClock = std::chrono::steady_clock;

// A running worker, as the parent sees it.
struct Worker {
    pid_t pid = -1;
    int fd = -1;  // read end of the report pipe
    std::optional<WorkerClock::time_point> deadline;
    std::string report;  // what it has written so far
    std::size_t tag = 0;  // the caller's: which job this is
    // A serving worker's (start_serving_worker): the parent's end of the job channel (-1 once
    // retired, and for a one-job worker), whether it has a job, and how many it was sent.
    int job_fd = -1;
    bool busy = false;
    std::size_t served = 0;
};

// Forks a worker that applies `limits.max_memory_bytes`, runs `job` and exits with its result.
// `others` are running workers whose pipes the new worker must not keep open. On failure to start,
// `outcome` says why and nothing is running.
std::optional<Worker> start_worker(const WorkerJob& job, const WorkerLimits& limits, const std::vector<Worker>& others,
                                   WorkerOutcome& outcome);

// A worker that serves jobs one after another (facet thumbs: one process for several objects
// that share a sandbox, so that each costs no fork, exit and fresh page faults): the parent sends a
// job's tag, the worker runs `job(tag, report, go_on)` and reports its end, then waits for the next.
// It exits when the parent retires it or when a job clears `go_on` (a job that leaves the process in
// a state the next one must not inherit). A crash or a timeout ends the worker and its job only.
using ServingJob = std::function<int(std::size_t tag, const WorkerReport&, bool& go_on)>;
std::optional<Worker> start_serving_worker(const ServingJob& job, const WorkerLimits& limits,
                                           const std::vector<Worker>& others, WorkerOutcome& outcome);

// Gives an idle serving worker job `tag`, with the job's own deadline; false if the worker is gone
// (it is then reported by wait_for_jobs).
bool send_job(Worker& w, std::size_t tag, const WorkerLimits& limits);

// Tells an idle serving worker that no job will come: it exits, and wait_for_jobs reaps it.
void retire(Worker& w);

// A job of a serving worker that ended: its tag, how (exited: the job's status), and how many jobs
// its worker had run before it (0: the job had a fresh process). With `after_job`, the worker
// itself ended abnormally once job `tag` was done and reported (a crash at exit, or a sanitizer's
// report: exit status 99).
struct JobEnd {
    std::size_t tag = 0;
    WorkerOutcome outcome;
    std::size_t served_before = 0;
    bool after_job = false;
};

// Waits until at least one job of the serving workers in `running` has ended (or passed its
// deadline: its worker is killed) and returns those. Workers that end are reaped and removed from
// `running`; those whose job ended stay, idle (busy false), for the caller to give another job or
// retire. Returns nothing if every worker ended without a job.
std::vector<JobEnd> wait_for_jobs(std::vector<Worker>& running);

// Runs one job in a worker and waits for it: for the status the job reports when it is done and
// its output flushed (the worker's exit that follows is not waited for: the caller exits soon
// after, and init reaps the worker), or, when none comes (a crash, sanitizer builds), for how
// the worker ended.
WorkerOutcome run_in_worker(const WorkerJob& job, const WorkerLimits& limits);

// One line for a worker that did not end by itself: "<input>: the importer crashed (SIGSEGV:
// Segmentation fault)", "<input>: gave up after 60 s (--timeout sets the limit)", ...
std::string describe_abnormal_end(const WorkerOutcome& outcome, const std::string& input, const WorkerLimits& limits);

// Whether the worker ended by itself with an exit status (as opposed to a signal, a timeout or
// not starting at all).
inline bool exited(const WorkerOutcome& o) { return o.end == WorkerOutcome::End::exited; }

// TEST HOOKS, for the tests of --timeout, of crashes and of the worker's exit only: when
// FACET_TEST_SLEEP_ON is set to a non-empty string, a worker whose input path contains it sleeps
// instead of working, as a file that hangs a reader would, until it is killed; FACET_TEST_CRASH_ON
// likewise makes it abort (SIGABRT), as a file that crashes a reader would; FACET_TEST_LINGER_ON
// makes it hang in its exit, after its job. Without the variables (as always outside the tests)
// they do nothing.
void test_hooks(const std::string& input);

// Confines this worker before it reads its model (facet/sandbox.hpp): files are read only in the
// model's folder and the resource folders (and what any job reads: the processor list,
// /dev/urandom), written only in the folders of `outputs` (and to outputs that are devices, such as
// /dev/null); no sockets, no exec, no new processes. What the kernel lacks is left out, never
// failing the job. No model (the built-in scene): nothing is read. TEST HOOK: FACET_TEST_SANDBOX_WITHOUT
// set to "landlock" or "seccomp" leaves that part out, as a kernel without it would.
// `other_model_dirs`: the folders of the other models a serving worker may read after this one
// (thumbs' --worker-sharing batch), readable too.
void confine_worker(const std::string& model, const std::vector<std::string>& outputs,
                    const std::vector<std::string>& resource_dirs, const std::vector<std::string>& other_model_dirs = {});

// What confine_worker applies on this machine, for --print-config: "seccomp, landlock (ABI 7)",
// "seccomp (this kernel has no Landlock)"; "none" when the job runs in facet's own process.
std::string describe_sandbox(bool isolated);

// Removes the temporaries write_file_atomic makes for `output` ("<name>.tmp<digits>"): a worker
// killed while writing leaves one behind.
void remove_temporaries(const std::filesystem::path& output);
// The same for every output named in `names` (file or folder names in `dir`), in one pass over the
// folder: what a killed run left, with the staging folders ("<name>.tmp<digits>") of views_output.hpp.
void remove_temporaries(const std::filesystem::path& dir, const std::unordered_set<std::string>& names);

// Lets glibc's malloc serve large buffers (the model, the framebuffers) from its heap and keep what
// is freed instead of mapping and unmapping each one: a job's memory freed after loading is reused
// by the render without new page faults; and serve every thread from that one heap. For a process
// that does one job and exits.
void keep_freed_memory_for_reuse();

// After keep_freed_memory_for_reuse, in the process that does the job (the worker, once its memory
// cap is set): the heap's next 128 MiB (a quarter of the cap at most, so the cap still binds) use
// transparent huge pages, so that a first touch faults in 2 MiB instead of 4 KiB. A job's buffers
// (the file, the mesh, the normals' scratch, the bins, the image) take tens of MB; with 4 KiB pages
// their page faults were a third of `facet render bunny00.off --size 512x512` (15 of 43 ms in the
// kernel). Only for jobs read by facet's own code: the free space it leaves above the heap's data
// turns some of assimp's reads past its buffers, which crash (and are reported), into garbage that
// loads (tests/regression/assimp_crashes/x_segv_a67c05d7.x did). Nothing changes where THP is
// "never" or the heap is not glibc's (sanitizer builds).
void use_huge_pages_for_heap(std::uint64_t max_memory_bytes);
// Whether a job of this model file may have the huge-page heap from its start: OFF and STL files,
// which facet reads nearly all itself, and assimp's readers of the others are not among those that
// read past their buffers (tests/regression/assimp_crashes). (A served worker's later jobs may have
// it whatever their files: assimp reads none there.)
bool huge_pages_suit(const std::string& path);

// Parses --max-memory: a number of MiB, or with a suffix K, M, G (KiB, MiB, GiB); 0: no limit.
std::optional<std::uint64_t> parse_memory_size(const std::string& text);

}  // namespace facet::cli
