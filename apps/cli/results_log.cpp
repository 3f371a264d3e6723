// facet command line: the results log (results_log.hpp): formatting, appending, reading back.
#include "results_log.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "json.hpp"

namespace facet::cli {
namespace {

namespace fs = std::filesystem;

// The furthest back a torn tail is looked for: a line holds an error message of a few KiB at most.
constexpr off_t k_max_line = 1 << 20;

Error io_error(const std::string& path, const std::string& what) { return Error{ErrorCode::io, path + ": " + what}; }

std::string milliseconds(const std::optional<double>& ms) {
    if (!ms) return "null";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", *ms);
    return buf;
}

std::string text_or_null(const std::string& s) { return s.empty() ? "null" : json::quote(s); }

// Cuts a tail that lacks its newline back to the last complete line. Under the lock.
Status cut_torn_tail(int fd, const std::string& path) {
    struct stat st {};
    if (fstat(fd, &st) != 0) return io_error(path, std::string("cannot read the log's size: ") + std::strerror(errno));
    if (st.st_size == 0) return Ok{};
    char last = '\n';
    if (pread(fd, &last, 1, st.st_size - 1) != 1) return io_error(path, std::string("cannot read the log: ") + std::strerror(errno));
    if (last == '\n') return Ok{};
    const off_t from = st.st_size > k_max_line ? st.st_size - k_max_line : 0;
    std::string tail(static_cast<std::size_t>(st.st_size - from), '\0');
    if (pread(fd, tail.data(), tail.size(), from) != static_cast<ssize_t>(tail.size()))
        return io_error(path, std::string("cannot read the log: ") + std::strerror(errno));
    const std::size_t newline = tail.rfind('\n');
    if (newline == std::string::npos && from > 0) return Ok{};  // not a line of ours: leave it (the reader skips it)
    const off_t keep = newline == std::string::npos ? 0 : from + static_cast<off_t>(newline) + 1;
    if (ftruncate(fd, keep) != 0) return io_error(path, std::string("cannot cut the log's torn last line: ") + std::strerror(errno));
    return Ok{};
}

}  // namespace

std::string format_log_line(const LogRecord& r) {
    std::string s = "{\"id\":" + text_or_null(r.id);
    s += ",\"path\":" + text_or_null(r.path);
    s += ",\"line\":" + (r.line ? std::to_string(r.line) : std::string("null"));
    s += std::string(",\"status\":") + (r.reason == FailReason::none ? "\"ok\"" : "\"failed\"");
    s += ",\"reason\":" + (r.reason == FailReason::none ? std::string("null") : json::quote(reason_code(r.reason)));
    s += ",\"error\":" + text_or_null(r.error);
    s += ",\"triangles\":" + (r.triangles ? std::to_string(*r.triangles) : std::string("null"));
    s += ",\"load_ms\":" + milliseconds(r.load_ms);
    s += ",\"render_ms\":" + milliseconds(r.render_ms);
    s += ",\"write_ms\":" + milliseconds(r.write_ms);
    s += ",\"total_ms\":" + milliseconds(r.total_ms);
    s += ",\"outputs\":[";
    for (std::size_t i = 0; i < r.outputs.size(); ++i) {
        if (i > 0) s += ',';
        s += json::quote(r.outputs[i]);
    }
    s += "],\"options_hash\":" + text_or_null(r.options_hash);
    return s + "}\n";
}

Result<LogWriter> LogWriter::open(const std::string& path) {
    std::error_code ec;
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty()) fs::create_directories(parent, ec);
    const int fd = ::open(path.c_str(), O_RDWR | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) return io_error(path, std::string("cannot open the log: ") + std::strerror(errno));
    LogWriter writer(path, fd);
    struct stat st {};
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return io_error(path, "the log must be a regular file");
    char first = '{';
    if (st.st_size > 0 && (pread(fd, &first, 1, 0) != 1 || first != '{'))
        return io_error(path, "is not a facet results log (its first line is not a JSON object); give another --log");
    return writer;
}

LogWriter::LogWriter(LogWriter&& other) noexcept : path_(std::move(other.path_)), fd_(other.fd_) { other.fd_ = -1; }

LogWriter::~LogWriter() {
    if (fd_ >= 0) ::close(fd_);
}

Status LogWriter::append(const std::string& line) {
    while (flock(fd_, LOCK_EX) != 0)
        if (errno != EINTR) return io_error(path_, std::string("cannot lock the log: ") + std::strerror(errno));
    Status status = cut_torn_tail(fd_, path_);
    for (std::size_t done = 0; status && done < line.size();) {
        const ssize_t n = ::write(fd_, line.data() + done, line.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) status = io_error(path_, std::string("cannot write to the log: ") + std::strerror(errno));
        else done += static_cast<std::size_t>(n);
    }
    flock(fd_, LOCK_UN);
    return status;
}

Result<LogContents> read_log(const std::string& path) {
    LogContents log;
    std::error_code ec;
    if (!fs::exists(path, ec)) return log;
    std::ifstream in(path, std::ios::binary);
    if (!in) return io_error(path, std::string("cannot open the log: ") + std::strerror(errno));
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) return io_error(path, "cannot read the log");
    const std::string text = buffer.str();
    using T = json::Value::Type;
    for (std::size_t pos = 0; pos < text.size();) {
        const std::size_t end = text.find('\n', pos);
        if (end == std::string::npos) {
            log.torn_tail = true;
            break;
        }
        const std::string_view line(text.data() + pos, end - pos);
        pos = end + 1;
        ++log.lines;
        Result<json::Value> v = json::parse(line);
        const json::Value* id = v ? v->find("id") : nullptr;
        const json::Value* status = v ? v->find("status") : nullptr;
        if (!id || !status || !status->is(T::string)) {
            ++log.unreadable;
            continue;
        }
        if (status->text != "ok" || !id->is(T::string)) continue;
        FinishedObject done;
        if (const json::Value* hash = v->find("options_hash"); hash && hash->is(T::string)) done.options_hash = hash->text;
        if (const json::Value* outputs = v->find("outputs"); outputs && outputs->is(T::array))
            for (const json::Value& o : outputs->items)
                if (o.is(T::string)) done.outputs.push_back(o.text);
        log.finished[id->text] = std::move(done);
    }
    return log;
}

}  // namespace facet::cli
