// facet command line: a collection's objects (collection.hpp): manifests read line by line into
// entries, ids turned into output names and shards.
#include "collection.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <unordered_map>

#include "json.hpp"

namespace facet::cli {
namespace {

namespace fs = std::filesystem;

Error usage(const std::string& message) { return Error{ErrorCode::invalid_argument, message}; }

std::string_view trim(std::string_view s) {
    const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; };
    while (!s.empty() && space(s.front())) s.remove_prefix(1);
    while (!s.empty() && space(s.back())) s.remove_suffix(1);
    return s;
}

// A whole number in [lo, hi] spelled in decimal digits only.
bool parse_count(std::string_view text, std::uint64_t lo, std::uint64_t hi, std::uint64_t& out) {
    if (text.empty() || text.size() > 19) return false;
    out = 0;
    for (const char c : text) {
        if (c < '0' || c > '9') return false;
        out = out * 10 + static_cast<std::uint64_t>(c - '0');
    }
    return out >= lo && out <= hi;
}

constexpr const char* k_known_keys = "\"id\", \"path\", \"size\", \"up_axis\", \"views\", \"passes\"";

// One JSON Lines entry into `e`; returns what is wrong with it (the id, when readable, is kept
// even then: the line still claims it).
std::string read_json_entry(const json::Value& v, ObjectEntry& e) {
    using T = json::Value::Type;
    if (!v.is(T::object)) return std::string("expected a JSON object, found ") + json::type_name(v.type);
    if (const json::Value* id = v.find("id")) {
        if (!id->is(T::string)) return std::string("\"id\" must be a string, found ") + json::type_name(id->type);
        e.id = id->text;
    }
    const json::Value* path = v.find("path");
    if (path && path->is(T::string) && !path->text.empty()) {
        e.path = path->text;
        if (!v.find("id")) e.id = path->text;
    }
    for (std::size_t i = 0; i < v.keys.size(); ++i) {
        const std::string& key = v.keys[i];
        const json::Value& value = v.items[i];
        if (key == "id") continue;
        if (key == "path") {
            if (!value.is(T::string) || value.text.empty())
                return "\"path\" must be a non-empty string, found " + (value.is(T::string) ? std::string("\"\"") : json::type_name(value.type));
        } else if (key == "size") {
            if (value.is(T::number)) {
                if (!(value.number >= 1 && value.number <= 1e6 && std::floor(value.number) == value.number))
                    return "\"size\" must be a whole number of pixels or \"WxH\"";
                e.options.size = std::to_string(static_cast<long>(value.number));
            } else if (value.is(T::string)) {
                e.options.size = value.text;
            } else {
                return std::string("\"size\" must be a number or \"WxH\", found ") + json::type_name(value.type);
            }
        } else if (key == "up_axis") {
            if (!value.is(T::string)) return std::string("\"up_axis\" must be \"y\" or \"z\", found ") + json::type_name(value.type);
            e.options.up_axis = value.text;
        } else if (key == "views") {
            if (!value.is(T::string)) return std::string("\"views\" must be a string such as \"orbit:8\", found ") + json::type_name(value.type);
            e.options.views = value.text;
        } else if (key == "passes") {
            if (value.is(T::string)) {
                std::stringstream in(value.text);
                for (std::string item; std::getline(in, item, ',');) e.options.passes.emplace_back(trim(item));
            } else if (value.is(T::array)) {
                for (const json::Value& item : value.items) {
                    if (!item.is(T::string)) return "\"passes\" must hold strings only";
                    e.options.passes.push_back(item.text);
                }
            } else {
                return std::string("\"passes\" must be an array of names or a comma-separated string, found ") +
                       json::type_name(value.type);
            }
            if (e.options.passes.empty()) return "\"passes\" must name at least one pass";
        } else {
            return "unknown key \"" + key + "\" (the keys are " + k_known_keys + ")";
        }
    }
    if (!path) return "no \"path\"";
    return {};
}

Result<std::string> read_all(const std::string& manifest) {
    std::ostringstream text;
    if (manifest == "-") {
        text << std::cin.rdbuf();
        return text.str();
    }
    std::error_code ec;
    if (fs::is_directory(manifest, ec)) return Error{ErrorCode::io, manifest + ": is a directory, not a manifest"};
    std::ifstream in(manifest, std::ios::binary);
    if (!in) return Error{ErrorCode::io, manifest + ": cannot open the manifest: " + std::strerror(errno)};
    text << in.rdbuf();
    if (in.bad()) return Error{ErrorCode::io, manifest + ": cannot read the manifest"};
    return text.str();
}

}  // namespace

const char* reason_code(FailReason r) {
    switch (r) {
    case FailReason::none: return "none";
    case FailReason::missing: return "missing";
    case FailReason::unreadable: return "unreadable";
    case FailReason::bad_file: return "bad_file";
    case FailReason::unsupported: return "unsupported";
    case FailReason::too_large: return "too_large";
    case FailReason::crashed: return "crashed";
    case FailReason::timed_out: return "timed_out";
    case FailReason::out_of_memory: return "out_of_memory";
    case FailReason::render_failed: return "render_failed";
    case FailReason::write_failed: return "write_failed";
    case FailReason::bad_entry: return "bad_entry";
    case FailReason::duplicate_id: return "duplicate_id";
    case FailReason::failed: return "failed";
    }
    return "failed";
}

const char* reason_label(FailReason r) {
    switch (r) {
    case FailReason::none: return "none";
    case FailReason::missing: return "missing file";
    case FailReason::unreadable: return "unreadable file";
    case FailReason::bad_file: return "not a valid model";
    case FailReason::unsupported: return "unsupported model";
    case FailReason::too_large: return "over a limit";
    case FailReason::crashed: return "crashed";
    case FailReason::timed_out: return "timed out";
    case FailReason::out_of_memory: return "out of memory";
    case FailReason::render_failed: return "render failed";
    case FailReason::write_failed: return "write failed";
    case FailReason::bad_entry: return "bad manifest entry";
    case FailReason::duplicate_id: return "duplicate id";
    case FailReason::failed: return "failed";
    }
    return "failed";
}

Result<Shard> parse_shard(const std::string& text) {
    const std::size_t slash = text.find('/');
    std::uint64_t k = 0, n = 0;
    if (slash == std::string::npos || !parse_count(std::string_view(text).substr(0, slash), 0, UINT32_MAX, k) ||
        !parse_count(std::string_view(text).substr(slash + 1), 1, UINT32_MAX, n))
        return usage("--shard must be K/N with whole numbers 0 <= K < N, got '" + text + "'");
    if (k >= n) return usage("--shard K/N needs K below N (shards are numbered from 0), got '" + text + "'");
    return Shard{static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(n)};
}

namespace {

// The settings of --print-config that say how the run goes, not what the image looks like; the
// options hash leaves them out, so that a resume on another machine (another kernel's sandbox),
// with other --threads or another --isa (same bytes) keeps what is done.
bool describes_the_run(std::string_view key) {
    static constexpr std::string_view k_keys[] = {"threads",   "isa",     "tile-size", "batch-triangles", "load-threads",
                                                  "isolation", "sandbox", "timeout",   "max-memory"};
    return std::find(std::begin(k_keys), std::end(k_keys), key) != std::end(k_keys);
}

}  // namespace

std::string options_hash(std::string_view config, const ObjectOptions& options) {
    std::string text = std::string("version = ") + FACET_VERSION + "\n";
    std::size_t pos = config.find('\n') + 1;  // after the comment line
    while (pos > 0 && pos < config.size()) {
        const std::size_t end = std::min(config.find('\n', pos), config.size() - 1);
        const std::string_view line = config.substr(pos, end - pos + 1);
        if (!describes_the_run(line.substr(0, line.find(" = ")))) text += line;
        pos = end + 1;
    }
    text += "views = " + options.views.value_or("") + "\npasses =";
    for (const std::string& p : options.passes) text += " " + p;
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(fnv1a_64(text + "\n")));
    return hex;
}

std::uint64_t fnv1a_64(std::string_view bytes) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const char c : bytes) {
        h ^= static_cast<unsigned char>(c);
        h *= 0x100000001b3ull;
    }
    return h;
}

std::uint64_t shard_hash(std::string_view id) {
    std::uint64_t h = fnv1a_64(id);
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return h;
}

std::uint32_t shard_of(std::string_view id, std::uint32_t count) { return static_cast<std::uint32_t>(shard_hash(id) % count); }

Result<std::string> output_stem_for_id(std::string_view id) {
    if (id.empty()) return usage("the id is empty");
    if (!json::valid_utf8(id)) return usage("the id is not valid UTF-8");
    std::string stem;
    for (std::size_t i = 0; i < id.size(); ++i) {
        const auto b = static_cast<unsigned char>(id[i]);
        const bool keep = (b >= 'A' && b <= 'Z') || (b >= 'a' && b <= 'z') || (b >= '0' && b <= '9') || b == '-' ||
                          b == '_' || b == '~' || (b == '.' && i > 0);
        if (keep) {
            stem += static_cast<char>(b);
        } else {
            char buf[4];
            std::snprintf(buf, sizeof buf, "%%%02X", b);
            stem += buf;
        }
    }
    if (stem.size() > k_max_stem)
        return usage("the id is too long for a file name (" + std::to_string(stem.size()) + " bytes once encoded, at most " +
                     std::to_string(k_max_stem) + ")");
    return stem;
}

namespace {

// Turns manifest lines into entries, one at a time, in file order.
class ManifestReader {
public:
    ManifestReader(const std::string& manifest, const Shard& shard)
        : name_(manifest == "-" ? "stdin" : manifest),
          base_(manifest == "-" ? fs::path() : fs::path(manifest).parent_path()),
          shard_(shard) {}

    // Whether `line` (trimmed) is an entry rather than a blank line or a comment; the first entry
    // sets the manifest's form.
    bool is_entry(std::string_view line) {
        if (line.empty() || line.front() == '#') return false;
        if (form_ == Form::unknown) form_ = line.front() == '{' ? Form::json_lines : Form::paths;
        return true;
    }

    void add(std::string_view raw, std::size_t line_number) {
        const std::string_view line = trim(raw);
        if (!is_entry(line)) return;
        ObjectEntry e;
        e.line = line_number;
        e.origin = name_ + ":" + std::to_string(line_number);
        std::string problem;
        if (form_ == Form::paths) {
            e.id = e.path = std::string(line);
        } else if (Result<json::Value> v = json::parse(line); !v) {
            problem = "not valid JSON: " + v.error().message;
        } else {
            problem = read_json_entry(*v, e);
        }
        // The shard of a line without an id is its text's, so that exactly one shard reports it.
        if (shard_of(e.id.empty() ? line : std::string_view(e.id), shard_.count) != shard_.index) return;
        if (!e.path.empty() && fs::path(e.path).is_relative() && !base_.empty()) e.path = (base_ / e.path).string();
        if (const std::string rig = e.options.views.value_or(""); rig.size() > 5 && rig.compare(0, 5, "file:") == 0)
            if (const fs::path cameras(rig.substr(5)); cameras.is_relative() && !base_.empty())
                e.options.views = "file:" + (base_ / cameras).string();
        if (problem.empty()) {
            if (Result<std::string> stem = output_stem_for_id(e.id)) e.stem = *stem;
            else problem = stem.error().message;
        }
        if (!e.id.empty()) {
            const auto [it, inserted] = first_line_.emplace(e.id, line_number);
            if (!inserted) {
                e.reason = FailReason::duplicate_id;
                e.error = e.origin + ": duplicate id " + json::quote(e.id) + " (first on line " + std::to_string(it->second) + ")";
            }
        }
        if (!problem.empty() && e.reason == FailReason::none) {
            e.reason = FailReason::bad_entry;
            e.error = e.origin + ": " + problem;
        }
        entries_.push_back(std::move(e));
    }

    const std::string& name() const { return name_; }
    std::vector<ObjectEntry> take() { return std::move(entries_); }

private:
    std::string name_;
    fs::path base_;
    Shard shard_;
    enum class Form { unknown, paths, json_lines } form_ = Form::unknown;
    std::unordered_map<std::string, std::size_t> first_line_;  // of each id in the shard
    std::vector<ObjectEntry> entries_;
};

// The lines at `only`'s offsets, after the form is read off the file's first entry.
Result<std::vector<ObjectEntry>> read_lines(const std::string& manifest, ManifestReader& reader,
                                            std::vector<ManifestLine> only) {
    if (manifest == "-") return usage("--manifest-lines needs a manifest file, not standard input");
    std::ifstream in(manifest, std::ios::binary);
    if (!in) return Error{ErrorCode::io, manifest + ": cannot open the manifest: " + std::strerror(errno)};
    std::string line;
    while (std::getline(in, line) && !reader.is_entry(trim(line))) {}
    std::sort(only.begin(), only.end(), [](const ManifestLine& a, const ManifestLine& b) { return a.offset < b.offset; });
    for (const ManifestLine& l : only) {
        in.clear();
        char before = '\n';
        if (l.offset > 0 && !(in.seekg(static_cast<std::streamoff>(l.offset - 1)) && in.get(before)))
            return usage(manifest + ": --manifest-lines offset " + std::to_string(l.offset) + " is past the end");
        if (before != '\n')
            return usage(manifest + ": --manifest-lines offset " + std::to_string(l.offset) + " is not the start of a line");
        in.seekg(static_cast<std::streamoff>(l.offset));
        std::getline(in, line);
        reader.add(line, l.number);
    }
    if (in.bad()) return Error{ErrorCode::io, manifest + ": cannot read the manifest"};
    return reader.take();
}

}  // namespace

Result<std::vector<ManifestLine>> parse_manifest_lines(const std::string& spec) {
    std::vector<ManifestLine> lines;
    std::stringstream in(spec);
    for (std::string item; std::getline(in, item, ',');) {
        const std::size_t colon = item.find(':');
        std::uint64_t offset = 0, number = 0;
        if (colon == std::string::npos || !parse_count(std::string_view(item).substr(0, colon), 0, UINT64_MAX / 10, offset) ||
            !parse_count(std::string_view(item).substr(colon + 1), 1, UINT64_MAX / 10, number))
            return usage("--manifest-lines takes OFFSET:LINE pairs, comma-separated (byte offsets of line starts and "
                         "their line numbers), got '" + item + "'");
        lines.push_back({offset, static_cast<std::size_t>(number)});
    }
    if (lines.empty() || spec.back() == ',') return usage("--manifest-lines takes OFFSET:LINE pairs, comma-separated, got '" + spec + "'");
    return lines;
}

Result<std::vector<ObjectEntry>> read_manifest(const std::string& manifest, const Shard& shard,
                                               const std::vector<ManifestLine>* only) {
    ManifestReader reader(manifest, shard);
    if (only) return read_lines(manifest, reader, *only);
    Result<std::string> text = read_all(manifest);
    if (!text) return text.error();
    std::size_t line_number = 0;
    for (std::size_t pos = 0; pos < text->size();) {
        std::size_t end = text->find('\n', pos);
        if (end == std::string::npos) end = text->size();
        reader.add(std::string_view(*text).substr(pos, end - pos), ++line_number);
        pos = end + 1;
    }
    return reader.take();
}

}  // namespace facet::cli
