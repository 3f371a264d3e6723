// facet view: where screenshots go. Next to the model (the current directory for the default
// scene), named after it with a counter that does not collide with existing files:
// bunny.ply -> bunny.screenshot-001.png, bunny.screenshot-002.png, ...
#pragma once

#include <string>

#include "facet/error.hpp"
#include "facet/image.hpp"

namespace facet::viewer {

// The first free name for a screenshot of `model_path` (empty: the default scene, named
// "facet.screenshot-NNN.png" in the current directory). Fails when 999 are taken.
Result<std::string> next_screenshot_path(const std::string& model_path);

// Writes the image as a PNG at next_screenshot_path; returns the path written.
Result<std::string> save_screenshot(const Image& image, const std::string& model_path);

}  // namespace facet::viewer
