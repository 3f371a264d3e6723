// facet io: the warnings of a read (import_notes.hpp).
#include "io/import_notes.hpp"

#include <algorithm>
#include <filesystem>

#include "io/resources.hpp"

namespace facet::io_detail {
namespace {

constexpr std::size_t k_max_logged_errors = 3;
constexpr std::size_t k_max_log_message = 1024;  // assimp's MAX_LOG_MESSAGE_LENGTH

// Logged "errors" about things facet does not use, or about files that are fine.
bool ignorable(std::string_view message) {
    for (std::string_view noise : {"No object detected to attach a new mesh instance",  // OBJ: usemtl before o/g
                                   "nimation", "Bone", "binormal", "tangent"})
        if (message.find(noise) != std::string_view::npos) return true;
    return false;
}

}  // namespace

void ImportNotes::error(std::string_view message) {
    error_reached_logger(message.size() > k_max_log_message ? std::string_view("<fixme: long message discarded>") : message);
}

void ImportNotes::error_reached_logger(std::string_view m) {
    if (ignorable(m)) return;
    if (m.find("out of range") != std::string_view::npos && m.find("ndex") != std::string_view::npos && !bad_index_)
        bad_index_ = std::string(m);
    if (std::find(distinct_.begin(), distinct_.end(), m) != distinct_.end()) return;
    ++total_;
    if (distinct_.size() < k_max_logged_errors) distinct_.emplace_back(m);
}

bool ImportNotes::may_open(const ResourceRoots& roots, const std::string& file) {
    if (roots.allows(file)) return true;
    std::error_code ec;
    if (std::filesystem::exists(file, ec) && std::find(refused_.begin(), refused_.end(), file) == refused_.end())
        refused_.push_back(file);
    return false;
}

std::string ImportNotes::refusals_text(const ResourceRoots& roots) const {
    std::string text;
    for (const std::string& file : refused_) text += "; " + roots.refusal(file);
    return text;
}

void ImportNotes::add_warnings(const std::string& path, const ResourceRoots& roots, LoadedModel& model) const {
    std::vector<std::string> front;
    for (const std::string& file : refused_) front.push_back(path + ": " + roots.refusal(file));
    if (total_ > 0) {
        std::string w = path + ": assimp reported problems and worked around them: ";
        for (std::size_t i = 0; i < distinct_.size(); ++i) w += (i ? "; " : "") + distinct_[i];
        if (total_ > distinct_.size()) w += " (and " + std::to_string(total_ - distinct_.size()) + " more)";
        front.push_back(std::move(w));
    }
    model.warnings.insert(model.warnings.begin(), front.begin(), front.end());
}

}  // namespace facet::io_detail
