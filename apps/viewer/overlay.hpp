// facet view: the on-screen overlay (frame rate, frame time, triangles, resolution, toggles, keys
// and messages), laid out as text lines and drawn with the viewer's own font into an Image: light
// text on a translucent dark box, transparent elsewhere, composited over the picture by the viewer.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "facet/image.hpp"
#include "view_state.hpp"

namespace facet::viewer {

struct OverlayInfo {
    std::string model;            // file name, or "default scene"
    std::size_t triangles = 0, points = 0, segments = 0;
    double fps = 0;               // presented frames per second lately; 0: idle (not measured)
    double frame_ms = 0;          // time to render the last frame (scene, resolve), milliseconds
    int width = 0, height = 0;    // the window's pixels
    int render_width = 0, render_height = 0;  // what was rendered (half size while dragging)
    int threads = 0;
    Toggles toggles;
    bool loading = false;
    std::string message;          // a status or error line; empty for none
    bool message_is_error = false;
};

struct OverlayLine {
    std::string text;
    Rgba8 colour;
};

// The overlay's text, one string per line, each at most `max_columns` characters (the message is
// wrapped, everything else cut).
std::vector<OverlayLine> overlay_lines(const OverlayInfo& info, int max_columns);

// The lines drawn into a box just large enough for them (padding around), at `scale` pixels per
// font pixel.
Image render_overlay(const std::vector<OverlayLine>& lines, int scale);

constexpr Rgba8 k_overlay_box{12, 13, 16, 176};
constexpr Rgba8 k_overlay_text{236, 238, 242, 255};
constexpr Rgba8 k_overlay_message_text{140, 220, 255, 255};
constexpr Rgba8 k_overlay_error_text{255, 130, 110, 255};
constexpr int k_overlay_padding = 4;  // font pixels

}  // namespace facet::viewer
