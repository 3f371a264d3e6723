// facet: textures. A Texture is an RGBA8 image with its full mip chain, sampled with
// perspective-correct UVs by the fragment stage: nearest, bilinear, or trilinear (bilinear on the
// two nearest mip levels, the level chosen from the UV derivatives), with repeat, clamp or mirror
// wrapping per axis. Decoding files (PNG, JPEG, ... via stb_image) is bounded by TextureLimits.
// Colours are sampled as stored (no sRGB conversion): the renderer's output is display-referred.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "facet/api.hpp"
#include "facet/defaults.hpp"
#include "facet/error.hpp"
#include "facet/image.hpp"
#include "facet/math/vec.hpp"

FACET_API_BEGIN
namespace facet {

enum class Wrap { repeat, clamp, mirror };
enum class Filter { nearest, bilinear, trilinear };

struct Sampler {
    Wrap wrap_u = Wrap::repeat;
    Wrap wrap_v = Wrap::repeat;
    Filter filter = Filter::trilinear;
};

// Where a texture is sampled for a mesh's uv: uv' = (m[0] u + m[1] v + m[2], m[3] u + m[4] v + m[5]),
// glTF's KHR_texture_transform (offset, rotation, scale) in uv space (v = 0 at the image's top).
struct UvTransform {
    float m[6] = {1, 0, 0, 0, 1, 0};
    bool is_identity() const { return m[0] == 1 && m[1] == 0 && m[2] == 0 && m[3] == 0 && m[4] == 1 && m[5] == 0; }
    Vec2 apply(Vec2 uv) const { return {m[0] * uv.x + m[1] * uv.y + m[2], m[3] * uv.x + m[4] * uv.y + m[5]}; }
    // The same without the offset: for the derivatives of uv.
    Vec2 apply_linear(Vec2 d) const { return {m[0] * d.x + m[1] * d.y, m[3] * d.x + m[4] * d.y}; }
};

// Texels of one level: columns [x0, x1) and rows [y0, y1); empty when x0 == x1.
struct TexelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct TextureLimits {
    int max_size = defaults::k_max_texture_size;            // per side
    std::size_t max_pixels = defaults::k_max_texture_pixels;  // width * height
};

class Texture {
public:
    // Builds the mip chain from `base` (each level a 2x2 box filter of the previous, odd sizes
    // rounded down, down to 1x1). An odd side n = 2m + 1 is filtered with area weights
    // (m - j, m, j + 1) / n, so no texel is dropped. Channels are rounded to nearest, halves up.
    // Throws FacetError (invalid_argument) for an empty image or one whose pixel count is not
    // width * height.
    explicit Texture(Image base);

    // Decodes an image file (any format stb_image reads). Errors name the file and the problem.
    static Result<std::shared_ptr<const Texture>> load(const std::string& path, const TextureLimits& limits = {});
    // Decodes an image held in memory (e.g. embedded in a glTF/GLB); `name` is used in errors.
    static Result<std::shared_ptr<const Texture>> decode(const void* bytes, std::size_t size, const std::string& name,
                                                         const TextureLimits& limits = {});

    int width() const { return levels_[0].width; }
    int height() const { return levels_[0].height; }
    int level_count() const { return static_cast<int>(levels_.size()); }
    const Image& level(int i) const { return levels_[static_cast<std::size_t>(i)]; }
    bool has_transparency() const { return has_transparency_; }  // any texel with alpha < 255
    // The smallest rectangle of level 0 holding every texel whose alpha is not 0 (empty when none
    // is): a bilinear sample of level 0 whose texels all lie outside has alpha 0 exactly.
    TexelRect alpha_bounds() const { return alpha_bounds_; }

    // Samples at uv (texel centres at (i + 0.5) / size, v = 0 at the top row of the image, as
    // glTF and OBJ-after-flip use it). The derivatives of uv along screen x and y choose the mip level.
    // Filter::nearest and Filter::bilinear always read level 0 (no mips); only trilinear uses lod.
    // Non-finite uv components are treated as 0: the result is always finite, in [0, 1].
    Vec4 sample(Vec2 uv, Vec2 duv_dx, Vec2 duv_dy, const Sampler& sampler) const;
    // Samples one explicit level of detail (0 = full size; fractional values blend two levels).
    // lod is clamped to [0, level_count() - 1]; NaN reads level 0.
    Vec4 sample_lod(Vec2 uv, float lod, const Sampler& sampler) const;
    // The level of detail sample() uses: log2 of the larger screen-pixel footprint in level-0
    // texels, rho = max(|duv_dx * size|, |duv_dy * size|) (OpenGL's formula). Unclamped; 0 for zero
    // or NaN derivatives, +inf for infinite ones.
    float lod(Vec2 duv_dx, Vec2 duv_dy) const;

private:
    std::vector<Image> levels_;
    bool has_transparency_ = false;
    TexelRect alpha_bounds_;
};

}  // namespace facet
FACET_API_END
