// facet command line: JSON parsing and quoting (json.hpp). A recursive-descent parser over the
// grammar of RFC 8259; the texts are single lines of a manifest or a log, so nothing is streamed.
#include "json.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace facet::cli::json {
namespace {

constexpr int k_max_depth = 64;

// The length of the UTF-8 sequence starting at s[i], or 0 when it is not a valid one.
std::size_t utf8_length(std::string_view s, std::size_t i) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char b = byte(i);
    if (b < 0x80) return 1;
    std::size_t n = 0;
    std::uint32_t cp = 0;
    if ((b & 0xe0) == 0xc0) n = 2, cp = b & 0x1f;
    else if ((b & 0xf0) == 0xe0) n = 3, cp = b & 0x0f;
    else if ((b & 0xf8) == 0xf0) n = 4, cp = b & 0x07;
    else return 0;
    if (i + n > s.size()) return 0;
    for (std::size_t k = 1; k < n; ++k) {
        if ((byte(i + k) & 0xc0) != 0x80) return 0;
        cp = (cp << 6) | (byte(i + k) & 0x3f);
    }
    constexpr std::uint32_t k_smallest[5] = {0, 0, 0x80, 0x800, 0x10000};  // shorter forms are overlong
    if (cp < k_smallest[n] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return 0;
    return n;
}

void append_utf8(std::string& out, std::uint32_t cp) {
    if (cp < 0x80) {
        out += static_cast<char>(cp);
    } else if (cp < 0x800) {
        out += static_cast<char>(0xc0 | (cp >> 6));
        out += static_cast<char>(0x80 | (cp & 0x3f));
    } else if (cp < 0x10000) {
        out += static_cast<char>(0xe0 | (cp >> 12));
        out += static_cast<char>(0x80 | ((cp >> 6) & 0x3f));
        out += static_cast<char>(0x80 | (cp & 0x3f));
    } else {
        out += static_cast<char>(0xf0 | (cp >> 18));
        out += static_cast<char>(0x80 | ((cp >> 12) & 0x3f));
        out += static_cast<char>(0x80 | ((cp >> 6) & 0x3f));
        out += static_cast<char>(0x80 | (cp & 0x3f));
    }
}

class Parser {
public:
    explicit Parser(std::string_view text) : s_(text) {}

    Result<Value> document() {
        Value v;
        skip_space();
        if (!value(v, 0)) return failure();
        skip_space();
        if (i_ != s_.size()) return fail("unexpected text after the JSON value"), failure();
        return v;
    }

private:
    std::string_view s_;
    std::size_t i_ = 0;
    std::string error_;

    Error failure() const { return Error{ErrorCode::bad_format, error_}; }

    bool fail(const std::string& what) {
        if (error_.empty()) error_ = "column " + std::to_string(i_ + 1) + ": " + what;
        return false;
    }

    void skip_space() {
        while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
    }

    bool literal(std::string_view word) {
        if (s_.substr(i_, word.size()) != word) return fail("expected a JSON value");
        i_ += word.size();
        return true;
    }

    bool value(Value& v, int depth) {
        if (depth >= k_max_depth) return fail("nested more than " + std::to_string(k_max_depth) + " levels deep");
        if (i_ >= s_.size()) return fail("expected a JSON value, found the end of the line");
        switch (s_[i_]) {
        case '{': return object(v, depth);
        case '[': return array(v, depth);
        case '"': v.type = Value::Type::string; return string(v.text);
        case 't': v.type = Value::Type::boolean; v.boolean = true; return literal("true");
        case 'f': v.type = Value::Type::boolean; v.boolean = false; return literal("false");
        case 'n': v.type = Value::Type::null; return literal("null");
        default: v.type = Value::Type::number; return number(v.number);
        }
    }

    bool object(Value& v, int depth) {
        v.type = Value::Type::object;
        ++i_;  // '{'
        skip_space();
        if (i_ < s_.size() && s_[i_] == '}') return ++i_, true;
        for (;;) {
            skip_space();
            if (i_ >= s_.size() || s_[i_] != '"') return fail("expected a key in double quotes");
            std::string key;
            if (!string(key)) return false;
            if (v.find(key)) return fail("the key \"" + key + "\" appears twice");
            skip_space();
            if (i_ >= s_.size() || s_[i_] != ':') return fail("expected ':' after the key");
            ++i_;
            skip_space();
            Value member;
            if (!value(member, depth + 1)) return false;
            v.keys.push_back(std::move(key));
            v.items.push_back(std::move(member));
            skip_space();
            if (i_ < s_.size() && s_[i_] == ',') {
                ++i_;
                continue;
            }
            if (i_ < s_.size() && s_[i_] == '}') return ++i_, true;
            return fail("expected ',' or '}'");
        }
    }

    bool array(Value& v, int depth) {
        v.type = Value::Type::array;
        ++i_;  // '['
        skip_space();
        if (i_ < s_.size() && s_[i_] == ']') return ++i_, true;
        for (;;) {
            skip_space();
            Value item;
            if (!value(item, depth + 1)) return false;
            v.items.push_back(std::move(item));
            skip_space();
            if (i_ < s_.size() && s_[i_] == ',') {
                ++i_;
                continue;
            }
            if (i_ < s_.size() && s_[i_] == ']') return ++i_, true;
            return fail("expected ',' or ']'");
        }
    }

    bool hex4(std::uint32_t& out) {
        if (i_ + 4 > s_.size()) return fail("expected four hex digits after \\u");
        out = 0;
        for (int k = 0; k < 4; ++k) {
            const char c = s_[i_++];
            out <<= 4;
            if (c >= '0' && c <= '9') out |= static_cast<std::uint32_t>(c - '0');
            else if (c >= 'a' && c <= 'f') out |= static_cast<std::uint32_t>(c - 'a' + 10);
            else if (c >= 'A' && c <= 'F') out |= static_cast<std::uint32_t>(c - 'A' + 10);
            else return --i_, fail("expected four hex digits after \\u");
        }
        return true;
    }

    bool string(std::string& out) {
        ++i_;  // '"'
        for (;;) {
            if (i_ >= s_.size()) return fail("the string is not closed");
            const char c = s_[i_];
            if (c == '"') return ++i_, true;
            if (static_cast<unsigned char>(c) < 0x20) return fail("a control character inside a string (escape it)");
            if (c != '\\') {
                const std::size_t n = utf8_length(s_, i_);
                if (n == 0) return fail("bytes that are not UTF-8 inside a string");
                out.append(s_.substr(i_, n));
                i_ += n;
                continue;
            }
            if (++i_ >= s_.size()) return fail("the string is not closed");
            const char e = s_[i_++];
            switch (e) {
            case '"': out += '"'; break;
            case '\\': out += '\\'; break;
            case '/': out += '/'; break;
            case 'b': out += '\b'; break;
            case 'f': out += '\f'; break;
            case 'n': out += '\n'; break;
            case 'r': out += '\r'; break;
            case 't': out += '\t'; break;
            case 'u': {
                std::uint32_t cp = 0;
                if (!hex4(cp)) return false;
                if (cp >= 0xdc00 && cp <= 0xdfff) return fail("a lone low surrogate in \\u escapes");
                if (cp >= 0xd800 && cp <= 0xdbff) {
                    std::uint32_t low = 0;
                    if (s_.substr(i_, 2) != "\\u") return fail("a high surrogate without its low half");
                    i_ += 2;
                    if (!hex4(low)) return false;
                    if (low < 0xdc00 || low > 0xdfff) return fail("a high surrogate without its low half");
                    cp = 0x10000 + ((cp - 0xd800) << 10) + (low - 0xdc00);
                }
                append_utf8(out, cp);
                break;
            }
            default: return --i_, fail(std::string("an unknown escape \\") + e);
            }
        }
    }

    bool number(double& out) {
        const std::size_t start = i_;
        const auto digits = [&] {
            const std::size_t from = i_;
            while (i_ < s_.size() && s_[i_] >= '0' && s_[i_] <= '9') ++i_;
            return i_ > from;
        };
        if (i_ < s_.size() && s_[i_] == '-') ++i_;
        if (i_ < s_.size() && s_[i_] == '0') ++i_;
        else if (!digits()) return i_ = start, fail("expected a JSON value");
        if (i_ < s_.size() && s_[i_] == '.') {
            ++i_;
            if (!digits()) return fail("expected digits after the decimal point");
        }
        if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
            ++i_;
            if (i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-')) ++i_;
            if (!digits()) return fail("expected digits in the exponent");
        }
        const std::string literal(s_.substr(start, i_ - start));
        out = std::strtod(literal.c_str(), nullptr);
        if (!std::isfinite(out)) return i_ = start, fail("a number too large for a double");
        return true;
    }
};

}  // namespace

const Value* Value::find(std::string_view key) const {
    if (type != Type::object) return nullptr;
    for (std::size_t i = 0; i < keys.size(); ++i)
        if (keys[i] == key) return &items[i];
    return nullptr;
}

Result<Value> parse(std::string_view text) { return Parser(text).document(); }

std::string quote(std::string_view s) {
    std::string out = "\"";
    out.reserve(s.size() + 2);
    for (std::size_t i = 0; i < s.size();) {
        const char c = s[i];
        const auto b = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (b < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", b);
            out += buf;
        } else if (b >= 0x80) {
            const std::size_t n = utf8_length(s, i);
            if (n == 0) {
                out += "\xef\xbf\xbd";  // U+FFFD REPLACEMENT CHARACTER
                ++i;
            } else {
                out.append(s.substr(i, n));
                i += n;
            }
            continue;
        } else {
            out += c;
        }
        ++i;
    }
    return out + "\"";
}

bool valid_utf8(std::string_view s) {
    for (std::size_t i = 0; i < s.size();) {
        const std::size_t n = utf8_length(s, i);
        if (n == 0) return false;
        i += n;
    }
    return true;
}

const char* type_name(Value::Type type) {
    switch (type) {
    case Value::Type::null: return "null";
    case Value::Type::boolean: return "true or false";
    case Value::Type::number: return "a number";
    case Value::Type::string: return "a string";
    case Value::Type::array: return "an array";
    case Value::Type::object: return "an object";
    }
    return "?";
}

}  // namespace facet::cli::json
