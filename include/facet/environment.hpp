// facet: image-based lighting for the lit mode. An Environment is the light arriving from every
// direction (linear RGB radiance), prefiltered once when it is made: specular levels for roughness
// 0..1 (GGX, by importance sampling), an irradiance term (spherical harmonics up to order 2) and, for
// all environments, the split-sum table (the GGX BRDF's scale and bias of F0 by n.v and roughness).
// Everything is computed with float/double arithmetic and portable functions only, so the same
// environment has the same bits on every machine. Made in code (Environment::studio: a neutral
// studio of soft boxes, no file) or from a Radiance HDR file (load_hdr: equirectangular, +Y up).
// Not the shading itself (shaders.hpp: shaders::Pbr) nor the tone mapping (tone_mapping.hpp).
//
// Directions are world space, +Y up. The maps are octahedral: direction d goes to the square
// p = (d.x, d.z) / (|d.x| + |d.y| + |d.z|), the lower hemisphere (d.y < 0) folded over the diamond's
// edges, texel (i, j) at u = (p.x + 1) / 2, v = (p.z + 1) / 2; each level is stored with a border of
// one texel copied across the folds, so that bilinear filtering needs no wrapping.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "facet/api.hpp"
#include "facet/error.hpp"
#include "facet/math/vec.hpp"

FACET_API_BEGIN
namespace facet {

// One octahedral map of RGB radiance: `size` x `size` texels plus the border, row-major from the
// border's top-left corner: texel (i, j), i and j in [-1, size], is at ((j + 1) (size + 2) + i + 1) * 3.
struct OctahedralLevel {
    int size = 0;
    std::size_t offset = 0;  // of its texel (-1, -1) in Environment::texels(), in floats
};

class Environment {
public:
    static constexpr int k_levels = 6;  // roughness 0, 0.2, ..., 1
    // Sizes of the specular levels: sharp enough at roughness 0 for a mirror's reflections at
    // thumbnail sizes, a texel per few degrees of the GGX lobe above it.
    static constexpr int k_level_sizes[k_levels] = {128, 64, 32, 16, 16, 16};

    // The built-in neutral studio: soft boxes over a grey room (README, "The lit mode"), prefiltered
    // when the library was built (its texels the library's constants, not copied) and shared; the
    // same bits every time and on every machine.
    static std::shared_ptr<const Environment> studio();
    // From equirectangular linear radiance (width x height RGB floats, row 0 the top, +Y up; the
    // image's centre column looks toward +X, as three.js and <model-viewer> map them; non-finite
    // or negative values count as 0). Throws FacetError (invalid_argument) for an empty image.
    static std::shared_ptr<const Environment> from_equirect(const float* rgb, int width, int height);
    // Reads a Radiance .hdr file (stb_image) within `max_pixels`. Errors name the file and the problem.
    static Result<std::shared_ptr<const Environment>> load_hdr(const std::string& path,
                                                               std::size_t max_pixels = std::size_t{64} << 20);

    // Made from a radiance function over the unit sphere (`radiance(direction)`, sampled at each
    // texel centre of the sharpest level): what studio() and from_equirect do.
    template <class F>
    static std::shared_ptr<const Environment> from_function(const F& radiance);

    // Every level with its border (OctahedralLevel), valid as long as the environment.
    std::span<const float> texels() const {
        return baked_ ? std::span<const float>(baked_, baked_count_) : std::span<const float>(texels_);
    }
    const OctahedralLevel& level(int i) const { return levels_[static_cast<std::size_t>(i)]; }
    // Irradiance as a diffuse surface's outgoing radiance per unit albedo (E / pi): the order-2
    // spherical-harmonic coefficients with the cosine lobe convolved in, 9 per channel (diffuse()).
    const std::array<Vec3, 9>& diffuse_sh() const { return sh_; }

    // The radiance seen toward unit `d` (bilinear in the sharpest level).
    Vec3 radiance(Vec3 d) const { return sample_level(0, d); }
    // Prefiltered radiance toward `r` for `lod` = roughness * (k_levels - 1): linear between the
    // two nearest levels, bilinear in each.
    Vec3 specular(Vec3 r, float lod) const;
    // A diffuse surface's radiance per unit albedo for unit normal n (the SH sum).
    Vec3 diffuse(Vec3 n) const;
    Vec3 sample_level(int level, Vec3 d) const;

private:
    Environment() = default;
    void build(const std::vector<float>& sharpest);  // sharpest: level 0's interior, size^2 RGB
    std::size_t lay_out_levels();                    // levels_ from k_level_sizes; the floats they take

    std::vector<float> texels_;  // every level with its border; empty for the studio's
    // The studio's texels: the library's baked constants, which live as long as the process, read
    // where they are rather than copied (280 KB) into each process's heap.
    const float* baked_ = nullptr;
    std::size_t baked_count_ = 0;
    std::array<OctahedralLevel, k_levels> levels_{};
    std::array<Vec3, 9> sh_{};
};

// Octahedral coordinates of a finite direction (not necessarily unit): u, v in [0, 1]; the zero
// vector (or NaN) gives the centre, +Y.
inline Vec2 octahedral_uv(Vec3 d) {
    const float l1 = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
    if (!(l1 > 0)) return {0.5f, 0.5f};
    float px = d.x / l1, pz = d.z / l1;
    if (d.y < 0) {
        const float fx = 1 - std::fabs(pz), fz = 1 - std::fabs(px);
        px = px >= 0 ? fx : -fx;
        pz = pz >= 0 ? fz : -fz;
    }
    return {px * 0.5f + 0.5f, pz * 0.5f + 0.5f};
}

// The unit direction at octahedral coordinates (u, v) in [0, 1] (octahedral_uv's inverse).
Vec3 octahedral_direction(Vec2 uv);

inline Vec3 Environment::sample_level(int i, Vec3 d) const {
    const OctahedralLevel& l = levels_[static_cast<std::size_t>(i)];
    const Vec2 uv = octahedral_uv(d);
    const float size = static_cast<float>(l.size);
    // Texel centres at (i + 0.5) / size; the border holds i = -1 and i = size.
    const float x = uv.x * size - 0.5f, y = uv.y * size - 0.5f;
    const float x0 = std::floor(x), y0 = std::floor(y);
    const float tx = x - x0, ty = y - y0;
    const int stride = l.size + 2;
    const float* row0 = texels().data() + l.offset + (static_cast<std::size_t>(y0 + 1) * stride + static_cast<std::size_t>(x0 + 1)) * 3;
    const float* row1 = row0 + static_cast<std::size_t>(stride) * 3;
    Vec3 c;
    for (int k = 0; k < 3; ++k) {
        const float top = row0[k] + (row0[3 + k] - row0[k]) * tx;
        const float bottom = row1[k] + (row1[3 + k] - row1[k]) * tx;
        c[static_cast<std::size_t>(k)] = top + (bottom - top) * ty;
    }
    return c;
}

inline Vec3 Environment::specular(Vec3 r, float lod) const {
    const float top = static_cast<float>(k_levels - 1);
    lod = lod > 0 ? (lod < top ? lod : top) : 0;  // NaN: 0
    const float l0 = std::floor(lod);
    const float t = lod - l0;
    const int i0 = static_cast<int>(l0);
    const Vec3 c0 = sample_level(i0, r);
    if (t == 0) return c0;  // also the last level
    return c0 + (sample_level(i0 + 1, r) - c0) * t;
}

// The real spherical harmonics up to order 2 at unit d (Y00; Y1-1, Y10, Y11; Y2-2, Y2-1, Y20, Y21,
// Y22). Projection and evaluation share it, so which axis plays z is only a naming.
inline std::array<float, 9> sh_basis(Vec3 d) {
    return {0.282094792f,
            0.488602512f * d.y,
            0.488602512f * d.z,
            0.488602512f * d.x,
            1.092548431f * d.x * d.y,
            1.092548431f * d.y * d.z,
            0.315391565f * (3 * d.z * d.z - 1),
            1.092548431f * d.x * d.z,
            0.546274215f * (d.x * d.x - d.y * d.y)};
}

inline Vec3 Environment::diffuse(Vec3 n) const {
    const std::array<float, 9> y = sh_basis(n);
    Vec3 c{};
    for (std::size_t i = 0; i < 9; ++i) c = c + sh_[i] * y[i];
    return max(c, Vec3{});
}

// The split-sum table of the GGX BRDF (Karis 2013): for n.v and roughness, the scale A and bias B
// such that the specular reflectance under uniform light is F0 A + B (Smith height-correlated
// visibility, importance-sampled with 256 Hammersley points per entry). k_split_sum_size^2
// entries, n.v = (i + 0.5) / size along rows, roughness = (j + 0.5) / size down the columns,
// A and B interleaved. Computed when the library was built; the same bits everywhere.
inline constexpr int k_split_sum_size = 32;
const std::vector<float>& split_sum_table();
// Bilinear lookup (clamped at the edges): {A, B}.
Vec2 split_sum(float n_dot_v, float roughness);

template <class F>
std::shared_ptr<const Environment> Environment::from_function(const F& radiance) {
    const int n = k_level_sizes[0];
    std::vector<float> sharpest(static_cast<std::size_t>(n) * n * 3);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec3 d = octahedral_direction({(static_cast<float>(i) + 0.5f) / static_cast<float>(n),
                                                 (static_cast<float>(j) + 0.5f) / static_cast<float>(n)});
            const Vec3 c = radiance(d);
            for (std::size_t k = 0; k < 3; ++k) {
                const float v = c[k];
                sharpest[(static_cast<std::size_t>(j) * n + static_cast<std::size_t>(i)) * 3 + k] = v > 0 && std::isfinite(v) ? v : 0.0f;
            }
        }
    std::shared_ptr<Environment> e(new Environment());
    e->build(sharpest);
    return e;
}

}  // namespace facet
FACET_API_END
