// facet view: a small bitmap font of its own (5x7 glyphs with one row of descender, printable ASCII)
// and text drawn straight into an Image, so the overlay needs no GUI library.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "facet/image.hpp"

namespace facet::viewer {

constexpr int k_glyph_width = 5, k_glyph_height = 8;  // rows 0..6 above the baseline, row 7 below
constexpr int k_glyph_advance = 6, k_line_height = 10;  // cell with one column and two rows of space

// One glyph: a row per element, top first; bit 4 is the leftmost column.
using GlyphRows = std::array<std::uint8_t, k_glyph_height>;

// The glyph of a character; characters outside printable ASCII (32..126) show as a hollow box.
const GlyphRows& glyph(char c);

// Width in pixels of a line of text at `scale` (pixels per font pixel), without trailing spacing.
int text_width(std::string_view text, int scale = 1);

// Draws `text` with its top-left corner at (x, y), every font pixel a scale x scale block of
// `colour` composited over the image (straight alpha). Clipped to the image.
void draw_text(Image& image, int x, int y, std::string_view text, Rgba8 colour, int scale = 1);

// Composites `colour` (straight alpha) over a rectangle of the image, clipped to the image.
void blend_rect(Image& image, int x, int y, int width, int height, Rgba8 colour);

// Straight-alpha "over": `src` composited onto `dst`.
Rgba8 blend_over(Rgba8 dst, Rgba8 src);

}  // namespace facet::viewer
