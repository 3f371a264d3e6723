// facet view: the interactive SDL2 window. Everything up to the pixels is shared with `facet render`
// (options, RenderPlan, Scene, Camera, render_scene); this adds the window, input and overlay.
#pragma once

#include <string>

#include "options.hpp"

namespace facet::viewer {

// Opens `model` (the built-in default scene when empty) in a window and runs until it is closed.
// Exit codes: 0 closed normally, 1 no window could be opened or the model file does not exist,
// 2 bad options.
int run_view(const std::string& model, bool spin, const cli::RenderOptions& options, bool camera_options_given);

}  // namespace facet::viewer
