// facet command line: JSON for the files it reads and writes a line at a time (manifests, the
// results log, `facet diff --json`). In: one JSON text (RFC 8259, strict); out: a small tree, or
// an error saying where the text went wrong. Writing is string quoting; there is no writer tree.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "facet/error.hpp"

namespace facet::cli::json {

struct Value {
    enum class Type { null, boolean, number, string, array, object };
    Type type = Type::null;
    bool boolean = false;
    double number = 0;
    std::string text;                                   // string: its UTF-8 bytes, unescaped
    // An array's items; an object's values, keys[i] naming items[i], in the text's order (keys
    // unique). Two vectors rather than one of pairs: a pair cannot hold the incomplete Value.
    std::vector<Value> items;
    std::vector<std::string> keys;

    bool is(Type t) const { return type == t; }
    // The member named `key` of an object, or null when there is none (or this is not an object).
    const Value* find(std::string_view key) const;
};

// Parses one JSON text (surrounding white space allowed, nothing else after it). Strings must be
// valid UTF-8 (escapes included: a lone surrogate is an error), objects must not repeat a key,
// nesting stops at 64 levels. The error names the column (1-based, in bytes) and what was expected.
Result<Value> parse(std::string_view text);

// `s` as a JSON string literal, quotes included. Bytes that are not valid UTF-8 become U+FFFD, so
// the line stays JSON whatever a file name or an error message holds.
std::string quote(std::string_view s);

// Whether `s` is valid UTF-8 (no overlong forms, no surrogates, nothing above U+10FFFF).
bool valid_utf8(std::string_view s);

// A name for a value's type in messages: "a string", "a number", ...
const char* type_name(Value::Type type);

}  // namespace facet::cli::json
