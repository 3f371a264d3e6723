// facet io, for tests: load_model with its dedicated fast readers turned off (every file through
// assimp, as before they existed), so that a test can check that both paths give the same Scene.
#pragma once

#include <string>

#include "facet/model.hpp"

namespace facet::io_detail {

Result<LoadedModel> load_model_through_assimp(const std::string& path, const LoadOptions& options = {});

}  // namespace facet::io_detail
