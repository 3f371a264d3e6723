// facet command line: the objects of a collection for `facet thumbs`. In: model files and
// directories from the command line, or a manifest (a text file of paths, or JSON Lines with an id
// and per-object options); out: one ObjectEntry per object, with its id, its model file, the stem
// its outputs are named by, and its shard. Neither loads nor renders; bad entries are marked, not
// thrown away, so that they are reported per object.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "facet/error.hpp"

namespace facet::cli {

// Why an object failed, as the log's "reason" and the summary's groups.
enum class FailReason {
    none,
    missing,            // the model file does not exist
    unreadable,         // it exists but cannot be read (permissions, an I/O error)
    bad_file,           // its bytes are not a valid model
    unsupported,        // a valid file facet does not handle
    too_large,          // beyond --max-triangles or another limit
    crashed,            // the worker died of a signal (the importer crashed)
    timed_out,          // past --timeout
    out_of_memory,      // past --max-memory, or the machine's memory
    render_failed,      // rendering threw
    write_failed,       // the output could not be written
    bad_entry,          // the manifest line: bad JSON, a bad key, a bad per-object option
    duplicate_id,       // an id seen on an earlier line
    failed,             // anything else
};
// "missing", "timed_out", ...: the log's spelling. And the summary's: "missing file", "timed out".
const char* reason_code(FailReason reason);
const char* reason_label(FailReason reason);

// Per-object options of a manifest entry, as written there (checked by the command that renders);
// unset: the command line's.
struct ObjectOptions {
    std::optional<std::string> size;     // "N" or "WxH"
    std::optional<std::string> up_axis;  // "y" or "z"
    std::optional<std::string> views;    // a camera rig (facet render --views; a relative file: is the manifest's)
    std::vector<std::string> passes;     // render passes (facet render --passes); empty: colour only
};

struct ObjectEntry {
    std::string id;      // names the outputs and picks the shard; empty only for a line without one
    std::string path;    // the model file (a manifest's relative paths resolved against its folder)
    std::string stem;    // outputs: <stem>.png, or with views or passes the folder <stem>/
    std::size_t line = 0;  // the manifest line; 0 for a command-line input
    std::string origin;    // where it was given, for messages: "<manifest>:<line>", or the input
    ObjectOptions options;
    FailReason reason = FailReason::none;  // set: a bad entry, failed without being rendered
    std::string error;                     // why, naming the manifest line
};

// --shard K/N: the objects whose id hashes into shard K of N.
struct Shard {
    std::uint32_t index = 0, count = 1;
};
// "K/N" with 0 <= K < N; the error names the option.
Result<Shard> parse_shard(const std::string& text);

// FNV-1a, 64 bits (offset basis 0xcbf29ce484222325, prime 0x100000001b3).
std::uint64_t fnv1a_64(std::string_view bytes);
// The stable hash of an id that picks its shard: FNV-1a 64 of the id's UTF-8 bytes, then
// MurmurHash3's 64-bit finalizer (fmix64), without which ids that differ only in their last
// characters ("chair-01", "chair-02") would share their high bits, and ids that differ only in the
// high bits of their characters their low ones.
std::uint64_t shard_hash(std::string_view id);
// The shard of an id among `count`: shard_hash(id) % count.
std::uint32_t shard_of(std::string_view id, std::uint32_t count);

// A file name stem for an id that cannot leave the output directory and that no other id maps
// to: bytes A-Z a-z 0-9 - _ . ~ are kept, every other byte becomes %XX (upper-case hex), and so
// does a leading '.', so "a/b" -> "a%2Fb", ".." -> "%2E.", "" is refused. Ids whose stem would be
// longer than k_max_stem bytes are refused too (a file name has at most 255).
constexpr std::size_t k_max_stem = 200;
Result<std::string> output_stem_for_id(std::string_view id);

// Reads a manifest ("-": standard input) and returns its entries that fall into `shard`, in file
// order, bad ones marked. The form is the first line's that is not blank or a comment (#): a '{'
// makes it JSON Lines, anything else a list of paths, one per line (surrounding white space
// trimmed; the id is the path as written). JSON Lines keys: "path" (required), "id" (default: the
// path), "size" (N or "WxH"), "up_axis", "views", "passes" (an array, or a comma-separated string).
// Relative paths are resolved against the manifest's folder (standard input: the current one). An
// id seen on an earlier line is a bad entry (duplicate_id; every entry with that id falls into the
// same shard, so each shard sees its duplicates); a line whose id cannot be read falls into the
// shard of its text. Fails only when the manifest itself cannot be read. With `only`, reads just
// those lines (each at its byte offset, in file order, numbered as given), so that a task of a few
// objects of a large manifest does not read all of it (facet.distributed's tasks).
struct ManifestLine {
    std::uint64_t offset = 0;  // of the line's first byte
    std::size_t number = 0;    // its line number, for messages and the log
};
Result<std::vector<ObjectEntry>> read_manifest(const std::string& manifest, const Shard& shard,
                                               const std::vector<ManifestLine>* only = nullptr);
// --manifest-lines: "OFFSET:LINE,OFFSET:LINE,...".
Result<std::vector<ManifestLine>> parse_manifest_lines(const std::string& spec);

// The options hash of an object (the log's "options_hash"): FNV-1a 64, as 16 hex digits, of facet's
// version, the lines of `config` (--print-config's text of the object's plan, its first line a
// comment) that shape the image, and the object's views and passes. The lines left out say how the
// run goes and cannot change a byte: threads, isa, tile-size, batch-triangles, load-threads,
// isolation, sandbox, timeout, max-memory.
std::string options_hash(std::string_view config, const ObjectOptions& options);

}  // namespace facet::cli
