// facet io: reading and writing image files. Writes are atomic: the data goes to a temporary file
// in the same directory, which is renamed over the destination only when complete, so a failed or
// interrupted write never leaves a partial file behind.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "facet/api.hpp"
#include "facet/error.hpp"
#include "facet/image.hpp"

FACET_API_BEGIN
namespace facet {

// How PNG files are compressed. The bytes depend on the image and the level alone, not on `threads`.
struct PngOptions {
    int level = 2;    // zlib's level, 0..9: 2 is several times faster than 6 and within ~10% of its size
    int threads = 0;  // the encoder's threads (row blocks deflated in parallel); 0: every core
    // deflate's run-length strategy (zlib's Z_RLE) instead of the level's string matching (levels 1
    // to 9 then write the same bytes): only repeats of the byte before are found, which suits smooth
    // shading on a plain background (facet thumbs: ~18% faster than level 2, ~2% smaller) better than
    // photographic textures (up to ~20% larger).
    bool runs_only = false;
};

// 8-bit PNG: RGB when every pixel is opaque (alpha 255), RGBA otherwise; read back, the pixels are the same.
Status write_png(const std::string& path, const Image& image, const PngOptions& options = {});
// The same PNG of width * height pixels at `pixels`, rows top first: for an image in memory that is
// not an Image's (facet render draws into memory it does not clear first).
Status write_png(const std::string& path, int width, int height, const Rgba8* pixels, const PngOptions& options = {});
// 8-bit and 16-bit grayscale PNG of width * height values, first row at the top.
Status write_png_gray8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& values);
Status write_png_gray16(const std::string& path, int width, int height, const std::vector<std::uint16_t>& values);
// 16-bit RGB PNG of width * height * 3 values (R, G, B per pixel), first row at the top.
Status write_png_rgb16(const std::string& path, int width, int height, const std::vector<std::uint16_t>& values);
// Any PNG, converted to RGBA8.
Result<Image> read_png(const std::string& path);

// Writes `bytes` to `path` through a temporary file and a rename.
Status write_file_atomic(const std::string& path, const void* bytes, std::size_t size);

}  // namespace facet
FACET_API_END
