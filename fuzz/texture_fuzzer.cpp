// Fuzz target: encoded images (JPEG through libjpeg-turbo; PNG, BMP, TGA, GIF, PSD, HDR, PNM, ...
// whatever stb_image reads) through facet::Texture::decode with small TextureLimits, then sampling the decoded texture
// with every filter and wrap mode at ordinary and hostile coordinates (NaN, inf, 1e30, huge or
// NaN derivatives, any lod).
// A finding is a crash, a sanitizer report, decode returning a texture over the limits, or a
// sample outside [0, 1] (the documented contract: always finite, in [0, 1]).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>

#include "facet/texture.hpp"

namespace {

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "texture_fuzzer: %s\n", what);
        std::abort();
    }
}

void check_colour(facet::Vec4 c) {
    for (float v : {c.x, c.y, c.z, c.w}) check(std::isfinite(v) && v >= 0.0f && v <= 1.0f, "sample outside [0, 1]");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const facet::TextureLimits limits{.max_size = 1024, .max_pixels = 128 * 128};
    auto decoded = facet::Texture::decode(data, size, "fuzz input", limits);
    if (!decoded) return 0;
    const facet::Texture& t = *decoded.value();
    check(t.width() >= 1 && t.height() >= 1, "empty texture");
    check(t.width() <= limits.max_size && t.height() <= limits.max_size &&
              static_cast<std::size_t>(t.width()) * static_cast<std::size_t>(t.height()) <= limits.max_pixels,
          "texture over the limits");
    check(t.level(t.level_count() - 1).width == 1 && t.level(t.level_count() - 1).height == 1, "mip chain not down to 1x1");

    constexpr float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const float coords[] = {0.0f, 0.5f, 1.0f, -0.25f, 1.75f, -1e-30f, 1e30f, -1e30f, inf, -inf, nan, 3.999999f};
    const float lods[] = {0.0f, 0.5f, 1.0f, 2.5f, 100.0f, -3.0f, inf, -inf, nan};
    const float derivs[] = {0.0f, 1e-3f, 0.1f, 1.0f, 1e30f, inf, nan};
    for (int f = 0; f < 3; ++f)
        for (int w = 0; w < 3; ++w) {
            const facet::Sampler s{static_cast<facet::Wrap>(w), static_cast<facet::Wrap>((w + 1) % 3),
                                   static_cast<facet::Filter>(f)};
            std::size_t n = 0;
            for (float u : coords)
                for (float v : coords) check_colour(t.sample_lod({u, v}, lods[n++ % std::size(lods)], s));
            for (float d : derivs) check_colour(t.sample({0.3f, 0.7f}, {d, 0.0f}, {0.0f, d}, s));
            for (float l : lods) check_colour(t.sample_lod({0.1f, 0.9f}, l, s));
        }
    return 0;
}
