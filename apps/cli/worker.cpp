// facet command line: jobs in worker processes (worker.hpp).
#include "worker.hpp"

#include <malloc.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>
#if defined(__linux__)
#include <sys/prctl.h>
#endif

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <new>
#include <string_view>
#include <thread>

#include "facet/defaults.hpp"
#include "facet/model.hpp"
#include "facet/sandbox.hpp"

namespace facet::cli {
namespace {

// Report records: a phase is k_phase_mark and one WorkerPhase character; figures are
// k_figures_mark and text up to the next mark; the error message is k_error_mark, its length in
// four bytes (little-endian) and the message; a serving worker ends each job with k_end_mark, the
// job's status in one byte, and whether it takes another job ('+') or exits ('.'). No mark can appear in a phase or in figures, and the message is
// counted, so a report parses unambiguously whatever the message holds.
constexpr char k_end_mark = '\x1c';
constexpr char k_figures_mark = '\x1d';
constexpr char k_phase_mark = '\x1e';
constexpr char k_error_mark = '\x1f';
// The parent reads a report only once the worker has closed the pipe (waking up for every phase
// would cost context switches on a busy machine), so the whole report must fit into the pipe's
// buffer (64 KiB on Linux, at least 4 KiB by POSIX) or the worker would block: a few phases and
// a message cut to this length do.
constexpr std::size_t k_max_message = 3500;

void write_all(int fd, const char* data, std::size_t size) {
    for (std::size_t done = 0; done < size;) {
        const ssize_t n = write(fd, data + done, size - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;  // the parent is gone: nobody to tell
        done += static_cast<std::size_t>(n);
    }
}

// The last phase, the figures and the error message of a job's report, up to its end record if
// there is one (a serving worker's finished job: `outcome` is then "exited" with the job's status
// and the length of the job's records is returned, to be taken off the report, with whether the
// worker goes on in `goes_on`); 0 otherwise (a one-job worker's report, or a job still running or
// cut short by the worker's end).
std::size_t parse_report(const std::string& report, WorkerOutcome& outcome, bool* goes_on = nullptr) {
    for (std::size_t i = 0; i < report.size();) {
        const char mark = report[i];
        if (mark == k_end_mark && i + 2 < report.size()) {
            outcome.end = WorkerOutcome::End::exited;
            outcome.status = static_cast<unsigned char>(report[i + 1]);
            if (goes_on) *goes_on = report[i + 2] == '+';
            return i + 3;
        }
        if (mark == k_phase_mark && i + 1 < report.size()) {
            outcome.phase = static_cast<WorkerPhase>(report[i + 1]);
            i += 2;
        } else if (mark == k_figures_mark) {
            const std::size_t end = report.find_first_of("\x1c\x1d\x1e\x1f", i + 1);
            outcome.figures = report.substr(i + 1, end == std::string::npos ? std::string::npos : end - i - 1);
            i = end == std::string::npos ? report.size() : end;
        } else if (mark == k_error_mark && i + 5 <= report.size()) {
            std::uint32_t length = 0;
            for (int b = 3; b >= 0; --b) length = length << 8 | static_cast<unsigned char>(report[i + 1 + static_cast<std::size_t>(b)]);
            outcome.message = report.substr(i + 5, length);
            i += 5 + std::size_t{length};
        } else {
            break;  // a record not complete yet
        }
    }
    return 0;
}

void close_quietly(int fd) {
    if (fd >= 0) close(fd);
}

// The worker's side, first: its limits.
void enter_worker(const WorkerLimits& limits, pid_t parent) {
#if defined(__linux__)
    // A parent that is killed (Ctrl-C reaches both, but a kill of the parent alone does not) takes
    // its worker along instead of leaving it hanging in a reader.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(1);
#endif
    if (limits.max_memory_bytes > 0 && memory_cap_supported()) {
        const rlimit cap{static_cast<rlim_t>(limits.max_memory_bytes), static_cast<rlim_t>(limits.max_memory_bytes)};
        setrlimit(RLIMIT_DATA, &cap);
    }
}

// Runs a job; an exception it lets out is its error, and status 1.
template <class Job>
int run_caught(const Job& job, const WorkerReport& report) {
    try {
        return job();
    } catch (const std::bad_alloc&) {
        report.error("out of memory");
    } catch (const std::exception& e) {
        report.error(e.what());
    } catch (...) {
        report.error("failed with an unknown exception");
    }
    return 1;
}

// Exits the worker. exit, not _exit: it flushes the worker's stdio (warnings, the --benchmark line)
// and lets LeakSanitizer check the worker in sanitizer builds; the parent flushed its own buffers
// before forking, so nothing is written twice.
[[noreturn]] void exit_worker(int status, int fd) {
    close(fd);
    std::fflush(nullptr);
    std::exit(status);
}

[[noreturn]] void run_worker(const WorkerJob& job, const WorkerLimits& limits, pid_t parent, int fd, bool report_end) {
    enter_worker(limits, parent);
    const WorkerReport report(fd);
    const int status = run_caught([&] { return job(report); }, report);
    // The job's output flushed, its status ends the report: the parent goes on at once (run_in_worker)
    // while this process exits (its memory unmapped: ~0.5 ms for a render). Without the end, the
    // parent waits for the exit and reaps this process.
    if (report_end) {
        std::fflush(nullptr);
        const char end[3] = {k_end_mark, static_cast<char>(status), '.'};
        write_all(fd, end, sizeof end);
    }
    exit_worker(status, fd);
}

bool read_exact(int fd, void* data, std::size_t size) {
    for (std::size_t done = 0; done < size;) {
        const ssize_t n = read(fd, static_cast<char*>(data) + done, size - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        done += static_cast<std::size_t>(n);
    }
    return true;
}

// A serving worker: jobs as the parent sends their tags, each report closed by its end record.
[[noreturn]] void run_serving_worker(const ServingJob& job, const WorkerLimits& limits, pid_t parent, int fd, int job_fd) {
    enter_worker(limits, parent);
    const WorkerReport report(fd);
    std::uint64_t tag = 0;
    bool go_on = true;
    while (go_on && read_exact(job_fd, &tag, sizeof tag)) {
        const int status = run_caught([&] { return job(static_cast<std::size_t>(tag), report, go_on); }, report);
        const char end[3] = {k_end_mark, static_cast<char>(status), go_on ? '+' : '.'};
        write_all(fd, end, sizeof end);
    }
    close(job_fd);
    exit_worker(0, fd);
}

std::string seconds_text(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", s);
    return buf;
}

// Who crashed, by the phase the worker had reached: while loading, the model reader (assimp).
std::string crashed_while(WorkerPhase phase) {
    switch (phase) {
    case WorkerPhase::starting:
    case WorkerPhase::loading:
        return "the importer crashed";
    case WorkerPhase::rendering:
        return "the worker process crashed while rendering";
    case WorkerPhase::writing:
    case WorkerPhase::writing_depth:
        break;
    }
    return "the worker process crashed while writing";
}

// Waits for a worker whose pipe has closed (it is exiting) and says how it ended.
WorkerOutcome reap(Worker& w) {
    WorkerOutcome o;
    int status = 0;
    while (waitpid(w.pid, &status, 0) < 0 && errno == EINTR) {}
    close_quietly(w.fd);
    w.fd = -1;
    parse_report(w.report, o);
    if (WIFSIGNALED(status)) {
        o.end = WorkerOutcome::End::signalled;
        o.status = WTERMSIG(status);
    } else {
        o.end = WorkerOutcome::End::exited;
        o.status = WIFEXITED(status) ? WEXITSTATUS(status) : 1;
    }
    return o;
}

WorkerOutcome kill_timed_out(Worker& w) {
    kill(w.pid, SIGKILL);
    while (waitpid(w.pid, nullptr, 0) < 0 && errno == EINTR) {}
    close_quietly(w.fd);
    w.fd = -1;
    WorkerOutcome o;
    parse_report(w.report, o);
    o.end = WorkerOutcome::End::timed_out;
    return o;
}

// Milliseconds until the nearest deadline (-1: none), for poll.
int poll_timeout_ms(const std::vector<Worker>& running) {
    std::optional<WorkerClock::time_point> first;
    for (const Worker& w : running)
        if (w.deadline && (!first || *w.deadline < *first)) first = w.deadline;
    if (!first) return -1;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(*first - WorkerClock::now()).count();
    return static_cast<int>(std::clamp<long long>(left + 1, 0, 60'000));
}

// Reads a worker's report pipe to its end (or an error: nothing more will come either way).
void read_to_end(Worker& w) {
    char buf[4096];
    ssize_t n;
    while ((n = read(w.fd, buf, sizeof buf)) > 0 || (n < 0 && errno == EINTR))
        if (n > 0) w.report.append(buf, static_cast<std::size_t>(n));
}

// Waits for `events` (or the end) on the workers' report pipes, until the nearest deadline.
std::vector<pollfd> poll_workers(const std::vector<Worker>& running, short events) {
    std::vector<pollfd> polled;
    for (const Worker& w : running) polled.push_back(pollfd{w.fd, events, 0});
    if (poll(polled.data(), polled.size(), poll_timeout_ms(running)) < 0 && errno != EINTR) {
        std::fprintf(stderr, "facet: poll failed: %s\n", std::strerror(errno));
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return polled;
}

}  // namespace

bool memory_cap_supported() { return !sanitizer_build(); }

bool orphans_are_reaped() {
    // The initial PID namespace has a fixed inode (PROC_PID_INIT_INO); without /proc, assume not.
    char link[64];
    const ssize_t n = readlink("/proc/self/ns/pid", link, sizeof link);
    return n > 0 && std::string_view(link, static_cast<std::size_t>(n)) == "pid:[4026531836]";
}

std::uint64_t default_max_memory_bytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return 0;
    return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) / defaults::k_memory_share_denominator *
           defaults::k_memory_share_numerator;
}

void WorkerReport::phase(WorkerPhase p) const {
    if (fd_ < 0) return;
    const char record[2] = {k_phase_mark, static_cast<char>(p)};
    write_all(fd_, record, sizeof record);
}

void WorkerReport::figures(const std::string& text) const {
    if (fd_ < 0) return;
    std::string record(1, k_figures_mark);
    for (const char c : text.substr(0, 256)) record += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
    write_all(fd_, record.data(), record.size());
}

void WorkerReport::error(const std::string& message) const {
    if (fd_ < 0) return;
    const auto length = static_cast<std::uint32_t>(std::min(message.size(), k_max_message));
    const char head[5] = {k_error_mark, static_cast<char>(length & 0xff), static_cast<char>(length >> 8 & 0xff),
                          static_cast<char>(length >> 16 & 0xff), static_cast<char>(length >> 24)};
    write_all(fd_, head, sizeof head);
    write_all(fd_, message.data(), length);
}

std::optional<WorkerClock::time_point> deadline_of(const WorkerLimits& limits) {
    if (limits.timeout_seconds <= 0) return std::nullopt;
    return WorkerClock::now() +
           std::chrono::duration_cast<WorkerClock::duration>(std::chrono::duration<double>(limits.timeout_seconds));
}

// Forks a worker that runs `child(report_fd, job_fd)` (which does not return); with `serving`, a
// job channel too: a socket pair rather than a pipe, so that sending to a worker that died fails
// (MSG_NOSIGNAL) instead of killing the parent with SIGPIPE.
template <class Child>
std::optional<Worker> fork_worker(const Child& child, bool serving, const std::vector<Worker>& others, WorkerOutcome& outcome) {
    outcome = WorkerOutcome{};
    int fds[2], jobs[2] = {-1, -1};
    if (pipe(fds) != 0 || (serving && socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, jobs) != 0)) {
        outcome.message = std::string("cannot start a worker process: ") + std::strerror(errno);
        if (serving && jobs[0] < 0) close(fds[0]), close(fds[1]);
        return std::nullopt;
    }
    std::fflush(nullptr);  // or the worker would write the parent's buffered output again
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        close_quietly(jobs[0]);
        for (const Worker& other : others) close_quietly(other.fd), close_quietly(other.job_fd);
        child(fds[1], jobs[1]);
    }
    close(fds[1]);
    close_quietly(jobs[1]);
    if (pid < 0) {
        close(fds[0]);
        close_quietly(jobs[0]);
        outcome.message = std::string("cannot start a worker process: ") + std::strerror(errno);
        return std::nullopt;
    }
    Worker w;
    w.pid = pid;
    w.fd = fds[0];
    w.job_fd = jobs[0];
    return w;
}

std::optional<Worker> start_worker(const WorkerJob& job, const WorkerLimits& limits, const std::vector<Worker>& others,
                                   WorkerOutcome& outcome) {
    const pid_t parent = getpid();
    // Not in sanitizer builds either: their reports at exit (LeakSanitizer's) are the exit status
    // the parent must see.
    static const bool report_end = !sanitizer_build() && orphans_are_reaped();
    std::optional<Worker> w =
        fork_worker([&](int fd, int) { run_worker(job, limits, parent, fd, report_end); }, false, others, outcome);
    if (w) w->deadline = deadline_of(limits);
    return w;
}

std::optional<Worker> start_serving_worker(const ServingJob& job, const WorkerLimits& limits,
                                           const std::vector<Worker>& others, WorkerOutcome& outcome) {
    const pid_t parent = getpid();
    return fork_worker([&](int fd, int job_fd) { run_serving_worker(job, limits, parent, fd, job_fd); }, true, others,
                       outcome);
}

bool send_job(Worker& w, std::size_t tag, const WorkerLimits& limits) {
    const std::uint64_t t = tag;
    w.tag = tag;
    w.busy = true;
    w.deadline = deadline_of(limits);
    ++w.served;
    return w.job_fd >= 0 && send(w.job_fd, &t, sizeof t, MSG_NOSIGNAL) == static_cast<ssize_t>(sizeof t);
}

void retire(Worker& w) {
    close_quietly(w.job_fd);
    w.job_fd = -1;
}

std::vector<JobEnd> wait_for_jobs(std::vector<Worker>& running) {
    std::vector<JobEnd> ended;
    while (ended.empty() && !running.empty()) {
        const std::vector<pollfd> polled = poll_workers(running, POLLIN);  // each report as it comes
        const WorkerClock::time_point now = WorkerClock::now();
        std::vector<Worker> still;
        for (std::size_t i = 0; i < running.size(); ++i) {
            Worker& w = running[i];
            bool closed = false;
            if (polled[i].revents != 0) {
                char buf[4096];
                ssize_t n;
                while ((n = read(w.fd, buf, sizeof buf)) < 0 && errno == EINTR) {}
                if (n > 0) w.report.append(buf, static_cast<std::size_t>(n));
                closed = n <= 0;
            }
            // The jobs it finished (one at a time: the next is sent only once this one is reported).
            WorkerOutcome o;
            bool goes_on = false;
            if (const std::size_t length = w.busy ? parse_report(w.report, o, &goes_on) : 0; length > 0) {
                ended.push_back({w.tag, std::move(o), w.served - 1});
                w.report.erase(0, length);
                w.busy = false;
                w.deadline.reset();
                if (!goes_on) retire(w);  // it is exiting: no job must be sent to it
            }
            if (closed) {
                retire(w);
                WorkerOutcome end = reap(w);
                // A job cut short by its worker's exit did not succeed, whatever the exit status.
                if (w.busy && exited(end) && end.status == 0) end.status = 1;
                // Between jobs a worker exits with 0 (a sanitizer's leak report at exit: 99).
                const bool bad_exit = !(exited(end) && end.status == 0);
                if (w.busy || bad_exit) ended.push_back({w.tag, std::move(end), w.served - 1, !w.busy});
            } else if (w.busy && w.deadline && now >= *w.deadline) {
                retire(w);
                ended.push_back({w.tag, kill_timed_out(w), w.served - 1});
            } else {
                still.push_back(std::move(w));
            }
        }
        running = std::move(still);
    }
    return ended;
}

WorkerOutcome run_in_worker(const WorkerJob& job, const WorkerLimits& limits) {
    WorkerOutcome outcome;
    std::optional<Worker> started = start_worker(job, limits, {}, outcome);
    if (!started) return outcome;
    std::vector<Worker> running{std::move(*started)};
    Worker& w = running.front();
    for (;;) {
        // The end of the report pipe (POLLHUP, always reported; no POLLIN): the worker closes it
        // once its job's status is reported, or at its exit.
        const std::vector<pollfd> polled = poll_workers(running, 0);
        if (polled.front().revents != 0) {
            read_to_end(w);
            WorkerOutcome o;
            if (parse_report(w.report, o) == 0) return reap(w);  // no status: how the process ended says it
            // The job reported its status: the worker is exiting, and is reaped by init once this
            // process (which returns this status and exits) has ended.
            close_quietly(w.fd);
            w.fd = -1;
            return o;
        }
        if (w.deadline && WorkerClock::now() >= *w.deadline) return kill_timed_out(w);
    }
}

std::string describe_abnormal_end(const WorkerOutcome& o, const std::string& input, const WorkerLimits& limits) {
    switch (o.end) {
    case WorkerOutcome::End::not_started:
        return input + ": " + o.message;
    case WorkerOutcome::End::timed_out:
        return input + ": gave up after " + seconds_text(limits.timeout_seconds) + " s (--timeout sets the limit)";
    case WorkerOutcome::End::signalled: {
        // SIGKILL that facet did not send: the kernel's OOM killer, most likely.
        const std::string hint = o.status == SIGKILL ? "; out of memory? --max-memory caps the worker"
                                 : o.status == SIGBUS && (o.phase == WorkerPhase::starting || o.phase == WorkerPhase::loading)
                                     ? mapped_file_crash_hint(input)
                                     : "";
        return input + ": " + crashed_while(o.phase) + " (" + describe_signal(o.status) + ")" + hint;
    }
    case WorkerOutcome::End::exited:
        break;
    }
    return input + ": the worker process failed (exit status " + std::to_string(o.status) + ")" +
           (o.message.empty() ? "" : ": " + o.message);
}

void test_hooks(const std::string& input) {
    auto on = [&](const char* variable) {
        const char* pattern = std::getenv(variable);
        return pattern && *pattern && input.find(pattern) != std::string::npos;
    };
    if (on("FACET_TEST_CRASH_ON")) std::abort();
    if (on("FACET_TEST_SLEEP_ON"))
        for (;;) pause();  // until the parent kills this worker
    if (on("FACET_TEST_LINGER_ON"))
        std::atexit([] {
            for (;;) pause();  // until the parent's end kills this worker (PR_SET_PDEATHSIG)
        });
}

void confine_worker(const std::string& model, const std::vector<std::string>& outputs,
                    const std::vector<std::string>& resource_dirs, const std::vector<std::string>& other_model_dirs) {
    namespace fs = std::filesystem;
    SandboxRules rules = sandbox_rules_for_model(model, resource_dirs);
    rules.read_dirs.insert(rules.read_dirs.end(), other_model_dirs.begin(), other_model_dirs.end());
    for (const std::string& out : outputs) {
        if (out.empty()) continue;
        const fs::path folder = fs::path(out).parent_path();
        rules.write_dirs.push_back(folder.empty() ? "." : folder.string());
        std::error_code ec;
        if (fs::exists(out, ec) && !fs::is_regular_file(out, ec)) rules.write_files.push_back(out);  // /dev/null
    }
    if (const char* without = std::getenv("FACET_TEST_SANDBOX_WITHOUT")) {
        const std::string_view w = without;
        rules.landlock = w.find("landlock") == std::string_view::npos;
        rules.seccomp = w.find("seccomp") == std::string_view::npos;
    }
    enter_sandbox(rules);  // what it could not apply, it leaves out: documented, not an error
}

std::string describe_sandbox(bool isolated) {
    if (!isolated) return "none";
    const int abi = landlock_abi();
    return abi > 0 ? "seccomp, landlock (ABI " + std::to_string(abi) + ")" : "seccomp (this kernel has no Landlock)";
}

void remove_temporaries(const std::filesystem::path& output) {
    remove_temporaries(output.has_parent_path() ? output.parent_path() : std::filesystem::path("."),
                       {output.filename().string()});
}

void remove_temporaries(const std::filesystem::path& dir, const std::unordered_set<std::string>& names) {
    namespace fs = std::filesystem;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        // "<name>.tmp<digits>", as write_file_atomic names them.
        const std::string name = it->path().filename().string();
        const std::size_t tmp = name.rfind(".tmp");
        if (tmp != std::string::npos && tmp + 4 < name.size() &&
            name.find_first_not_of("0123456789", tmp + 4) == std::string::npos && names.count(name.substr(0, tmp)))
            fs::remove_all(it->path(), ec);  // a file, or a staging folder (views_output.hpp)
    }
}

std::optional<std::uint64_t> parse_memory_size(const std::string& text) {
    if (text.empty() || text.size() > 20) return std::nullopt;
    std::size_t digits = 0;
    while (digits < text.size() && text[digits] >= '0' && text[digits] <= '9') ++digits;
    if (digits == 0) return std::nullopt;
    const std::string suffix = text.substr(digits);
    int shift = 20;  // MiB without a suffix
    if (suffix == "K" || suffix == "k") shift = 10;
    else if (suffix == "G" || suffix == "g") shift = 30;
    else if (!(suffix.empty() || suffix == "M" || suffix == "m")) return std::nullopt;
    const std::uint64_t n = std::strtoull(text.substr(0, digits).c_str(), nullptr, 10);
    if (n > (std::uint64_t{1} << (63 - shift))) return std::nullopt;  // would not fit
    return n << shift;
}

void keep_freed_memory_for_reuse() {
    // glibc's largest mmap threshold (32 MiB on 64-bit); larger blocks are still mapped.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    // One heap for all threads: each thread would otherwise get an arena of its own, mapped anew,
    // grown by an mprotect call at a time and faulted in 4 KiB pages (the render's bins: 700
    // faults for the bunny), outside the heap that use_huge_pages_for_heap prepares. A job's
    // threads allocate their scratch once, so they hardly contend for the one lock.
    mallopt(M_ARENA_MAX, 1);
}

bool huge_pages_suit(const std::string& path) {
    const std::string ext = model_extension(path);
    return ext == "off" || ext == "stl";
}

void use_huge_pages_for_heap(std::uint64_t max_memory_bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    std::uint64_t bytes = std::uint64_t{128} << 20;
    if (max_memory_bytes > 0) bytes = std::min(bytes, max_memory_bytes / 4);
    // The heap grows by `bytes` (address space: nothing is touched) through glibc's top pad, and
    // that range is advised to use transparent huge pages. Freed, it stays the heap's top
    // (keep_freed_memory_for_reuse's trim threshold), and the job's buffers are carved from it.
    constexpr std::uintptr_t k_huge_page = 2 << 20;
    constexpr int k_default_top_pad = 128 << 10;  // glibc's M_TOP_PAD
    // The advised range begins at a 2 MiB boundary at least 64 KiB above the heap's end, and the
    // block that grows the heap ends just under it: nothing in the range is touched before it is
    // advised (a 4 KiB page touched first, as the header malloc writes after a block was when the
    // heap ended less than 1 MiB under the boundary, leaves the rest of its 2 MiB to 4 KiB pages).
    const auto begin = reinterpret_cast<std::uintptr_t>(sbrk(0));
    const std::uintptr_t first = (begin + (64 << 10) + k_huge_page - 1) & ~(k_huge_page - 1);
    // A block larger than the free top of the heap (keepcost, which ends at `begin`) makes malloc
    // grow it, by the block's excess plus the pad; below the mmap threshold, or it would be mapped
    // on its own. Its chunk ends at most 23 bytes past the block, and malloc's next header follows.
    const std::size_t block = mallinfo2().keepcost + (first - begin) - 64;
    if (block >= (32 << 20)) return;
    mallopt(M_TOP_PAD, static_cast<int>(bytes));
    void* grow = std::malloc(block);
    mallopt(M_TOP_PAD, k_default_top_pad);
    const auto end = reinterpret_cast<std::uintptr_t>(sbrk(0));
    const std::uintptr_t last = end & ~(k_huge_page - 1);
    if (!grow || last <= first) {
        std::free(grow);
        return;
    }
    madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
    std::free(grow);
    // Below `first` lies up to 2 MiB of the heap's free top, faulted in 4 KiB pages: the job's
    // first buffers landed there (the bunny's file: up to 640 faults). A block that is never freed
    // fills it (address space only: nothing in it is touched), so that they are carved from the
    // advised range.
    static void* volatile below_first = nullptr;  // volatile: a block never read could be left out
    const std::uintptr_t top = end - mallinfo2().keepcost;  // where the heap's free top begins
    if (first > top + (64 << 10)) below_first = std::malloc(first - top);
    (void)below_first;
#else
    (void)max_memory_bytes;
#endif
}

}  // namespace facet::cli
