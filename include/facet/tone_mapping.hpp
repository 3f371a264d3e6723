// facet: from the lit mode's linear radiance to display values. Exposure scales the radiance, a tone
// mapper brings it into [0, 1] (Khronos PBR Neutral by default, ACES on request, or a plain clamp),
// and the sRGB transfer function encodes it for an 8-bit image. Also the sRGB decoding of colour
// textures. Plain arithmetic and portable_pow only: the SIMD kernels repeat these operation for
// operation. Not the shading (shaders::Pbr) nor the quantization to bytes (to_rgba8).
#pragma once

#include <string_view>

#include "facet/api.hpp"
#include "facet/math/portable_pow.hpp"
#include "facet/math/vec.hpp"

FACET_API_BEGIN
namespace facet {

enum class ToneMapping {
    neutral,  // Khronos PBR Neutral: colours up to 0.76 kept as they are, highlights rolled off to white
    aces,     // ACES filmic as three.js (and <model-viewer>'s "aces") computes it: Hill's RRT+ODT fit
    linear,   // none: clamped to [0, 1]
};
// Parses "neutral", "aces", "linear"; false for anything else.
bool parse_tone_mapping(std::string_view name, ToneMapping& out);
const char* to_string(ToneMapping t);

// Khronos PBR Neutral (the Khronos 3D Commerce tone mapper, 2024), exactly its published formula:
//   x = min(r, g, b); offset = x < 0.08 ? x - 6.25 x^2 : 0.04; c -= offset
//   peak = max(r, g, b); if peak < 0.76 return c
//   d = 0.24; new_peak = 1 - d^2 / (peak + d - 0.76); c *= new_peak / peak
//   g = 1 - 1 / (0.15 (peak - new_peak) + 1); return mix(c, new_peak, g)
inline Vec3 tone_map_pbr_neutral(Vec3 c) {
    constexpr float k_start_compression = 0.8f - 0.04f, k_desaturation = 0.15f;
    const float x = c.x < c.y ? (c.x < c.z ? c.x : c.z) : (c.y < c.z ? c.y : c.z);
    const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
    c = c - Vec3{offset, offset, offset};
    const float peak = c.x > c.y ? (c.x > c.z ? c.x : c.z) : (c.y > c.z ? c.y : c.z);
    if (peak < k_start_compression) return c;
    constexpr float d = 1 - k_start_compression;
    const float new_peak = 1 - d * d / (peak + d - k_start_compression);
    c = c * (new_peak / peak);
    const float g = 1 - 1 / (k_desaturation * (peak - new_peak) + 1);
    return c + (Vec3{new_peak, new_peak, new_peak} - c) * g;
}

// ACES filmic as three.js's ACESFilmicToneMapping (Stephen Hill's fit): c / 0.6, the input matrix,
// RRT+ODT's rational fit, the output matrix, clamped to [0, 1].
inline float aces_rrt_odt_fit(float v) {
    const float a = v * (v + 0.0245786f) - 0.000090537f;
    const float b = v * (0.983729f * v + 0.4329510f) + 0.238081f;
    return a / b;
}
inline Vec3 tone_map_aces(Vec3 c) {
    c = c * (1 / 0.6f);
    const Vec3 in{0.59719f * c.x + 0.35458f * c.y + 0.04823f * c.z, 0.07600f * c.x + 0.90834f * c.y + 0.01566f * c.z,
                  0.02840f * c.x + 0.13383f * c.y + 0.83777f * c.z};
    const Vec3 f{aces_rrt_odt_fit(in.x), aces_rrt_odt_fit(in.y), aces_rrt_odt_fit(in.z)};
    const Vec3 out{1.60475f * f.x - 0.53108f * f.y - 0.07367f * f.z, -0.10208f * f.x + 1.10813f * f.y - 0.00605f * f.z,
                   -0.00327f * f.x - 0.07276f * f.y + 1.07602f * f.z};
    return clamp(out, 0.0f, 1.0f);
}

inline Vec3 tone_map(Vec3 c, ToneMapping t) {
    switch (t) {
        case ToneMapping::neutral: return tone_map_pbr_neutral(c);
        case ToneMapping::aces: return tone_map_aces(c);
        case ToneMapping::linear: break;
    }
    return c;
}

// The sRGB transfer functions (IEC 61966-2-1), with portable_pow: encode a linear value in [0, 1]
// (others are clamped) for display, and decode a stored colour channel to linear.
inline float linear_to_srgb(float c) {
    c = c > 0 ? (c < 1 ? c : 1) : 0;  // NaN: 0
    return c <= 0.0031308f ? 12.92f * c : 1.055f * portable_pow(c, 1 / 2.4f) - 0.055f;
}
inline float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : portable_pow((c + 0.055f) / 1.055f, 2.4f);
}

}  // namespace facet
FACET_API_END
