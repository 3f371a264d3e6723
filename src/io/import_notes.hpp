// facet io: what a reader reports besides the scene, as facet turns it into warnings: the errors
// assimp's importers log while working around bad data (one warning listing the first few distinct
// ones; an out-of-range index is an error instead), and the files a model named that its resource
// folders do not allow (a warning each, first). The assimp path fills it from assimp's logger and
// IOSystem (assimp_import.cpp); facet's own readers, which mirror assimp's, note the same messages
// at the same moments, so that both give the same warnings. No reading here.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "facet/model.hpp"

namespace facet::io_detail {

class ResourceRoots;

class ImportNotes {
public:
    // An error as assimp's Logger::error passes it to the logger: messages longer than 1024
    // characters arrive as a placeholder.
    void error(std::string_view message);
    // An error as it reaches facet's logger (after Logger::error's length check).
    void error_reached_logger(std::string_view message);

    // Whether `file` may be opened (roots.allows); if not and the file exists, it is noted as
    // refused (once). What assimp's IOSystem asks before opening anything.
    bool may_open(const ResourceRoots& roots, const std::string& file);

    const std::optional<std::string>& bad_index() const { return bad_index_; }

    // "; <reason>" for every refused file, for an error message.
    std::string refusals_text(const ResourceRoots& roots) const;

    // Puts the warnings at the front of the model's: one per refused file, then the logged errors'.
    void add_warnings(const std::string& path, const ResourceRoots& roots, LoadedModel& model) const;

private:
    std::vector<std::string> distinct_;  // the first few distinct messages, in order
    std::size_t total_ = 0;
    std::optional<std::string> bad_index_;
    std::vector<std::string> refused_;  // files refused that exist, in order, each once
};

}  // namespace facet::io_detail
