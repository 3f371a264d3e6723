// facet view: overlay text and its image.
#include "overlay.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "facet/primitive_counts.hpp"
#include "font.hpp"

namespace facet::viewer {
namespace {

std::string format(const char* fmt, auto... args) {
    char buf[256];
    std::snprintf(buf, sizeof buf, fmt, args...);
    return buf;
}

const char* on_off(bool b) { return b ? "on" : "off"; }

// Splits a message into lines of at most `columns`, at spaces where possible.
void wrap(const std::string& text, std::size_t columns, Rgba8 colour, std::vector<OverlayLine>& out) {
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = std::min(text.size(), start + columns);
        if (end < text.size()) {
            const std::size_t space = text.rfind(' ', end);
            if (space != std::string::npos && space > start) end = space;
        }
        out.push_back({text.substr(start, end - start), colour});
        start = end;
        while (start < text.size() && text[start] == ' ') ++start;
    }
}

}  // namespace

std::vector<OverlayLine> overlay_lines(const OverlayInfo& i, int max_columns) {
    const std::size_t columns = static_cast<std::size_t>(std::max(max_columns, 8));
    const Toggles& t = i.toggles;
    std::vector<std::string> lines;
    lines.push_back(i.loading ? i.model + "  loading..." : i.model + "  " + describe_primitives(i.triangles, i.points, i.segments));
    std::string rate = i.fps > 0 ? format("%.1f fps", i.fps) : std::string("-- fps");
    std::string size = format("%dx%d", i.width, i.height);
    if (i.render_width != i.width || i.render_height != i.height) size += format(" (%dx%d)", i.render_width, i.render_height);
    lines.push_back(format("%s  %.1f ms  %s  ssaa %d  %d threads", rate.c_str(), i.frame_ms, size.c_str(), t.ssaa, i.threads));
    lines.push_back(format("%s  wire %s  cull %s  spin %s  up %s  %s", to_string(t.shading), on_off(t.wireframe),
                           t.cull_back ? "back" : "off", on_off(t.spin), t.up_axis == UpAxis::y ? "y" : "z",
                           t.orthographic ? "ortho" : "persp"));
    lines.push_back("L-drag orbit  R-drag pan  wheel zoom");
    lines.push_back("F fit  R reset  1-7 views  U up axis  P ortho");
    lines.push_back("M shading  W wire  C cull  Space spin");
    lines.push_back("A ssaa  S screenshot  H hide  Q quit");
    std::vector<OverlayLine> out;
    for (std::string& l : lines) {
        if (l.size() > columns) l.resize(columns);
        out.push_back({std::move(l), k_overlay_text});
    }
    if (!i.message.empty()) wrap(i.message, columns, i.message_is_error ? k_overlay_error_text : k_overlay_message_text, out);
    return out;
}

Image render_overlay(const std::vector<OverlayLine>& lines, int scale) {
    scale = std::max(scale, 1);
    int text_w = 0;
    for (const OverlayLine& l : lines) text_w = std::max(text_w, text_width(l.text, scale));
    const int pad = k_overlay_padding * scale;
    Image image;
    image.width = text_w + 2 * pad;
    image.height = static_cast<int>(lines.size()) * k_line_height * scale + 2 * pad - (k_line_height - k_glyph_height) * scale;
    image.height = std::max(image.height, 2 * pad);
    image.pixels.assign(static_cast<std::size_t>(image.width) * image.height, k_overlay_box);
    for (std::size_t n = 0; n < lines.size(); ++n)
        draw_text(image, pad, pad + static_cast<int>(n) * k_line_height * scale, lines[n].text, lines[n].colour, scale);
    return image;
}

}  // namespace facet::viewer
