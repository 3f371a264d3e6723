// facet shade: the names of the tone mappers (facet/tone_mapping.hpp), for options and --print-config.
#include "facet/tone_mapping.hpp"

namespace facet {
namespace {
constexpr struct {
    ToneMapping mapping;
    const char* name;
} k_names[] = {{ToneMapping::neutral, "neutral"}, {ToneMapping::aces, "aces"}, {ToneMapping::linear, "linear"}};
}  // namespace

bool parse_tone_mapping(std::string_view name, ToneMapping& out) {
    for (const auto& n : k_names)
        if (name == n.name) {
            out = n.mapping;
            return true;
        }
    return false;
}

const char* to_string(ToneMapping t) {
    for (const auto& n : k_names)
        if (n.mapping == t) return n.name;
    return "?";
}

}  // namespace facet
