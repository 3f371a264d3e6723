// facet command line: the results log of `facet thumbs --log` (JSON Lines, one line per object as
// it finishes) and reading it back for --resume. In: what became of each object; out: lines
// appended so that a run killed at any moment leaves no line a reader trips on. It decides nothing
// about which objects to render.
#pragma once

#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "collection.hpp"
#include "facet/error.hpp"

namespace facet::cli {

// One object's line: {"id", "path", "line", "status" ("ok" or "failed"), "reason", "error",
// "triangles", "load_ms", "render_ms", "write_ms", "total_ms", "outputs", "options_hash"}, unknown
// values null. README, "Collections", documents each key.
struct LogRecord {
    std::string id;        // empty (null): a manifest line without a readable id
    std::string path;      // the model file; empty (null) when the line had none
    std::size_t line = 0;  // the manifest line; 0 (null): a command-line input
    FailReason reason = FailReason::none;  // none: "status": "ok"
    std::string error;
    std::optional<std::size_t> triangles;
    std::optional<double> load_ms, render_ms, write_ms;
    double total_ms = 0;               // from starting its worker to its end, as this process saw it
    std::vector<std::string> outputs;  // file names relative to the output directory
    std::string options_hash;          // empty (null): the options were never resolved (a bad entry)
};

// The record as one line of JSON, with its newline.
std::string format_log_line(const LogRecord& record);

// An open log, appended to a line at a time. Each line is one write() with O_APPEND under an
// exclusive flock, so lines from several processes sharing the log never interleave; under the
// same lock a tail without its newline (a writer killed in the middle of a line, or a full disk)
// is cut off first, so the next line never glues onto a torn one.
class LogWriter {
public:
    // Creates the file (and its folder) if needed. Refuses a file whose first line is not a JSON
    // object: not a facet log, whose tail it must not cut.
    static Result<LogWriter> open(const std::string& path);
    LogWriter(LogWriter&& other) noexcept;
    LogWriter& operator=(LogWriter&&) = delete;
    ~LogWriter();
    Status append(const std::string& line);
    const std::string& path() const { return path_; }

private:
    LogWriter(std::string path, int fd) : path_(std::move(path)), fd_(fd) {}
    std::string path_;
    int fd_ = -1;
};

// What --resume needs of a finished object: the latest "ok" line of its id.
struct FinishedObject {
    std::string options_hash;
    std::vector<std::string> outputs;
};

struct LogContents {
    std::unordered_map<std::string, FinishedObject> finished;  // by id
    std::size_t lines = 0;           // complete lines read
    std::size_t unreadable = 0;      // complete lines that are not a log record (skipped)
    bool torn_tail = false;          // the file ends in a line without its newline (skipped)
};

// Reads a log; a missing file reads as empty. Lines that do not parse are counted and skipped, and
// so is a last line without its newline (a writer may be in the middle of it).
Result<LogContents> read_log(const std::string& path);

}  // namespace facet::cli
