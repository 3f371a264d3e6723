// facet shade: textures. In: an RGBA8 Image (or encoded image bytes, decoded within TextureLimits:
// JPEG by libjpeg-turbo, everything else by stb_image). Out: a Texture holding the full mip chain, and sampled colours (Vec4 in [0, 1])
// for the fragment stage, which passes uv and its screen-space derivatives.
//
// Mip levels: each level is an area-weighted box filter of the previous one. An even side halves
// with a 2-tap average; an odd side n = 2m + 1 > 1 becomes m texels, each covering n / m source
// texels, i.e. a 3-tap filter with weights (m - j, m, j + 1) / n for output texel j (the polyphase
// box of "Non-Power-of-Two Mipmapping", NVIDIA 2001). Unlike dropping the last texel, this keeps
// every texel's contribution and the image's mean, and does not shift the picture.
#include <stb_image.h>
#include <turbojpeg.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "facet/math/portable_pow.hpp"
#include "facet/texture.hpp"

namespace facet {
namespace {

// ---- mip chain -----------------------------------------------------------------------------------

// The source texels that make up one destination texel along one axis, with integer weights that
// sum to `denominator`, so the 2D filter can be evaluated exactly in integers and rounded once.
struct AxisFilter {
    std::array<int, 3> index{};
    std::array<std::uint32_t, 3> weight{};
    int taps = 0;
    std::uint32_t denominator = 1;
};

int half_size(int n) { return n > 1 ? n / 2 : 1; }

AxisFilter axis_filter(int src_size, int dst_index) {
    AxisFilter f;
    if (src_size == 1) {  // this axis is done: the texel is copied
        f.index[0] = 0, f.weight[0] = 1, f.taps = 1, f.denominator = 1;
    } else if (src_size % 2 == 0) {
        f.index = {2 * dst_index, 2 * dst_index + 1, 0};
        f.weight = {1, 1, 0};
        f.taps = 2, f.denominator = 2;
    } else {
        const auto m = static_cast<std::uint32_t>(src_size / 2);
        const auto j = static_cast<std::uint32_t>(dst_index);
        f.index = {2 * dst_index, 2 * dst_index + 1, 2 * dst_index + 2};
        f.weight = {m - j, m, j + 1};
        f.taps = 3, f.denominator = static_cast<std::uint32_t>(src_size);
    }
    return f;
}

Image downsample(const Image& src) {
    Image dst;
    dst.width = half_size(src.width);
    dst.height = half_size(src.height);
    dst.pixels.resize(static_cast<std::size_t>(dst.width) * dst.height);
    std::vector<AxisFilter> columns(static_cast<std::size_t>(dst.width));
    for (int x = 0; x < dst.width; ++x) columns[static_cast<std::size_t>(x)] = axis_filter(src.width, x);
    for (int y = 0; y < dst.height; ++y) {
        const AxisFilter fy = axis_filter(src.height, y);
        for (int x = 0; x < dst.width; ++x) {
            const AxisFilter& fx = columns[static_cast<std::size_t>(x)];
            // 64 bits: the denominator reaches side² for odd sides, times 255.
            std::array<std::uint64_t, 4> sum{};
            for (int ty = 0; ty < fy.taps; ++ty)
                for (int tx = 0; tx < fx.taps; ++tx) {
                    const std::uint64_t w = std::uint64_t{fy.weight[ty]} * fx.weight[tx];
                    const Rgba8 t = src.at(fx.index[tx], fy.index[ty]);
                    sum[0] += w * t.r, sum[1] += w * t.g, sum[2] += w * t.b, sum[3] += w * t.a;
                }
            const std::uint64_t den = std::uint64_t{fx.denominator} * fy.denominator;
            // Round to nearest, halves up: 127.5 becomes 128.
            auto q = [den](std::uint64_t s) { return static_cast<std::uint8_t>((s + den / 2) / den); };
            dst.at(x, y) = {q(sum[0]), q(sum[1]), q(sum[2]), q(sum[3])};
        }
    }
    return dst;
}

void validate(const Image& base) {
    if (base.width < 1 || base.height < 1)
        throw FacetError(Error{ErrorCode::invalid_argument, "Texture: the image is empty (" +
                                                                std::to_string(base.width) + "x" +
                                                                std::to_string(base.height) + ")"});
    if (base.pixels.size() != static_cast<std::size_t>(base.width) * static_cast<std::size_t>(base.height))
        throw FacetError(Error{ErrorCode::invalid_argument,
                               "Texture: the image is " + std::to_string(base.width) + "x" +
                                   std::to_string(base.height) + " but holds " +
                                   std::to_string(base.pixels.size()) + " pixels"});
}

// ---- sampling ------------------------------------------------------------------------------------

// A non-finite coordinate would make every index computation below undefined; 0 is as good a
// defined answer as any, and keeps NaN out of the framebuffer.
[[gnu::always_inline]] inline float finite_or_zero(float v) { return std::isfinite(v) ? v : 0.0f; }

// Folds a coordinate into [0, 1] according to the wrap mode. Folding the coordinate before taking
// texel indices (rather than wrapping arbitrary integer indices) keeps every index small even for
// uv = 1e30, where u * size would overflow an int. The bilinear footprint can then step at most one
// texel outside [0, size), which wrap_index() settles.
[[gnu::always_inline]] inline float wrap_coord(float u, Wrap wrap) {
    switch (wrap) {
        case Wrap::repeat: return u - std::floor(u);  // may round to exactly 1 for tiny negative u
        case Wrap::clamp: return clamp(u, 0.0f, 1.0f);
        case Wrap::mirror: {
            const float t = u - 2.0f * std::floor(u * 0.5f);  // [0, 2]: one period is a tile and its mirror image
            return t > 1.0f ? 2.0f - t : t;
        }
    }
    return 0.0f;
}

// Index i in [-1, size] of a bilinear footprint, brought into [0, size). With the coordinate
// already folded, repeat wraps around while clamp and mirror stay on the edge texel (the mirror
// image of the texel just outside is the edge texel itself).
[[gnu::always_inline]] inline int wrap_index(int i, int size, Wrap wrap) {
    if (wrap == Wrap::repeat) return i < 0 ? size - 1 : (i >= size ? 0 : i);
    return std::clamp(i, 0, size - 1);
}

// Colour channels stay in 0..255 until the end, so a texel centre returns exactly texel / 255.
[[gnu::always_inline]] inline Vec4 texel(const Image& level, int x, int y) {
    const Rgba8 t = level.at(x, y);
    return {float(t.r), float(t.g), float(t.b), float(t.a)};
}

int nearest_index(float u, int size, Wrap wrap) {
    const float f = wrap_coord(u, wrap) * static_cast<float>(size);  // [0, size]
    return std::min(static_cast<int>(f), size - 1);  // u folded to exactly 1 belongs to the last texel
}

Vec4 nearest(const Image& level, Vec2 uv, const Sampler& s) {
    return texel(level, nearest_index(uv.x, level.width, s.wrap_u), nearest_index(uv.y, level.height, s.wrap_v));
}

// The two texels either side of coordinate u (texel centres at (i + 0.5) / size) and the weight
// of the second.
struct Footprint {
    int i0, i1;
    float t;
};

[[gnu::always_inline]] inline Footprint footprint(float u, int size, Wrap wrap) {
    const float x = wrap_coord(u, wrap) * static_cast<float>(size) - 0.5f;  // [-0.5, size - 0.5]
    const float x0 = std::floor(x);
    const int i0 = static_cast<int>(x0);
    return {wrap_index(i0, size, wrap), wrap_index(i0 + 1, size, wrap), x - x0};
}

[[gnu::always_inline]] inline Vec4 bilinear(const Image& level, Vec2 uv, const Sampler& s) {
    const Footprint fx = footprint(uv.x, level.width, s.wrap_u);
    const Footprint fy = footprint(uv.y, level.height, s.wrap_v);
    const Vec4 top = mix(texel(level, fx.i0, fy.i0), texel(level, fx.i1, fy.i0), fx.t);
    const Vec4 bottom = mix(texel(level, fx.i0, fy.i1), texel(level, fx.i1, fy.i1), fx.t);
    return mix(top, bottom, fy.t);
}

// ---- decoding ------------------------------------------------------------------------------------

// stb_image takes the encoded size as an int.
constexpr std::size_t k_max_encoded_bytes = INT_MAX;

constexpr unsigned char k_png_signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

std::uint32_t read_be32(const unsigned char* p) {
    return std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 | std::uint32_t{p[3]};
}

struct Size {
    std::uint64_t width = 0, height = 0;
};

// stbi_info refuses a PNG whose decoded size would pass 1 GiB ("too large") without saying how
// large, so for PNG the size is read from the IHDR chunk directly: a huge texture is then reported
// as over the limits, with its size, rather than as a corrupt file.
bool png_header_size(const unsigned char* p, std::size_t size, Size& out) {
    if (size < 24 || std::memcmp(p, k_png_signature, 8) != 0 || std::memcmp(p + 12, "IHDR", 4) != 0) return false;
    out = {read_be32(p + 16), read_be32(p + 20)};
    return true;
}

std::string size_text(std::uint64_t w, std::uint64_t h) { return std::to_string(w) + "x" + std::to_string(h); }

std::optional<Error> check_limits(const std::string& name, Size s, const TextureLimits& limits) {
    const auto max_side = static_cast<std::uint64_t>(std::max(limits.max_size, 0));
    // Sides are below 2^32, so the product cannot overflow 64 bits.
    if (s.width <= max_side && s.height <= max_side && s.width * s.height <= limits.max_pixels) return std::nullopt;
    return Error{ErrorCode::limit_exceeded,
                 name + ": the image is " + size_text(s.width, s.height) + ", over the texture limits (" +
                     std::to_string(limits.max_size) + " per side, " + std::to_string(limits.max_pixels) +
                     " pixels)"};
}

Error bad_format(const std::string& name, const char* why) {
    return Error{ErrorCode::bad_format,
                 name + ": not a readable image (" + (why ? why : "unknown reason") + ")"};
}

struct StbiFree {
    void operator()(stbi_uc* p) const { stbi_image_free(p); }
};

// JPEG through libjpeg-turbo: 1.3-2x faster than stb_image, and its accurate integer IDCT, colour
// conversion and fancy upsampling give the same bytes with and without its SIMD code (checked on
// this machine with JSIMD_FORCENONE and JSIMD_FORCESSE2 against AVX2: 48 files, all subsamplings),
// so the pixels do not depend on the ISA. They differ from stb_image's by a few levels (the
// JPEG-textured golden images were made again for it). CMYK and YCCK files, which TurboJPEG does
// not convert to RGBA, stay with stb_image (std::nullopt).
struct TurboFree {
    void operator()(void* handle) const { tjDestroy(handle); }
};

std::optional<Result<Image>> decode_jpeg(const unsigned char* p, std::size_t size, const std::string& name,
                                         const TextureLimits& limits) {
    if (size < 3 || p[0] != 0xFF || p[1] != 0xD8 || p[2] != 0xFF) return std::nullopt;
    const std::unique_ptr<void, TurboFree> tj(tjInitDecompress());
    if (!tj) return Result<Image>(Error{ErrorCode::io, name + ": cannot start the JPEG decoder"});
    const auto bytes = static_cast<unsigned long>(size);
    int w = 0, h = 0, subsampling = 0, colour_space = 0;
    if (tjDecompressHeader3(tj.get(), p, bytes, &w, &h, &subsampling, &colour_space) != 0)
        return Result<Image>(bad_format(name, tjGetErrorStr2(tj.get())));
    if (colour_space == TJCS_CMYK || colour_space == TJCS_YCCK) return std::nullopt;
    // The size is checked before a single pixel is allocated.
    if (w < 1 || h < 1) return Result<Image>(bad_format(name, "it decodes to an image without pixels"));
    if (auto e = check_limits(name, {static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(h)}, limits))
        return Result<Image>(*e);
    Image image;
    image.width = w;
    image.height = h;
    image.pixels.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    // Warnings stop the decode: a truncated file is an error, not an image finished in grey.
    if (tjDecompress2(tj.get(), p, bytes, reinterpret_cast<unsigned char*>(image.pixels.data()), w, 0, h, TJPF_RGBA,
                      TJFLAG_ACCURATEDCT | TJFLAG_STOPONWARNING) != 0)
        return Result<Image>(bad_format(name, tjGetErrorStr2(tj.get())));
    return Result<Image>(std::move(image));
}

Result<std::vector<unsigned char>> read_file(const std::string& path) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
    if (!file) return Error{ErrorCode::io, path + ": cannot open: " + std::strerror(errno)};
    std::vector<unsigned char> bytes;
    std::array<unsigned char, 1 << 16> chunk;
    for (;;) {
        const std::size_t n = std::fread(chunk.data(), 1, chunk.size(), file.get());
        bytes.insert(bytes.end(), chunk.data(), chunk.data() + n);
        if (bytes.size() > k_max_encoded_bytes)
            return Error{ErrorCode::limit_exceeded, path + ": the file is larger than the 2 GiB stb_image can read"};
        if (n < chunk.size()) break;
    }
    // A directory opens fine on Linux; reading it is what fails (EISDIR).
    if (std::ferror(file.get())) return Error{ErrorCode::io, path + ": cannot read: " + std::strerror(errno)};
    return bytes;
}

}  // namespace

Texture::Texture(Image base) {
    validate(base);
    has_transparency_ = std::any_of(base.pixels.begin(), base.pixels.end(), [](Rgba8 t) { return t.a < 255; });
    TexelRect& b = alpha_bounds_;
    b = {base.width, base.height, 0, 0};
    for (int y = 0; y < base.height; ++y)
        for (int x = 0; x < base.width; ++x)
            if (base.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(base.width) + static_cast<std::size_t>(x)].a != 0)
                b = {std::min(b.x0, x), std::min(b.y0, y), std::max(b.x1, x + 1), std::max(b.y1, y + 1)};
    if (b.x1 == 0) b = {};
    levels_.push_back(std::move(base));
    while (levels_.back().width > 1 || levels_.back().height > 1) levels_.push_back(downsample(levels_.back()));
}

Result<std::shared_ptr<const Texture>> Texture::load(const std::string& path, const TextureLimits& limits) {
    auto bytes = read_file(path);
    if (!bytes) return bytes.error();
    return decode(bytes->data(), bytes->size(), path, limits);
}

Result<std::shared_ptr<const Texture>> Texture::decode(const void* bytes, std::size_t size, const std::string& name,
                                                       const TextureLimits& limits) {
    if (!bytes || size == 0) return bad_format(name, "no data");
    if (size > k_max_encoded_bytes)
        return Error{ErrorCode::limit_exceeded, name + ": the encoded image is larger than the 2 GiB stb_image can read"};
    const auto* p = static_cast<const stbi_uc*>(bytes);
    const int len = static_cast<int>(size);
    if (std::optional<Result<Image>> jpeg = decode_jpeg(p, size, name, limits)) {
        if (!*jpeg) return jpeg->error();
        return std::shared_ptr<const Texture>(std::make_shared<const Texture>(std::move(**jpeg)));
    }

    // The header first: the size is checked before a single pixel is allocated.
    int w = 0, h = 0, channels = 0;
    Size declared;
    if (stbi_info_from_memory(p, len, &w, &h, &channels))
        declared = {static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(h)};
    else if (!png_header_size(p, size, declared))
        return bad_format(name, stbi_failure_reason());
    if (auto e = check_limits(name, declared, limits)) return *e;

    // stb_image's failure reason is thread-local in Debian's build (compiled with STBI_THREAD_LOCAL);
    // its global vertical-flip flag is not, so this thread's flag is set: row 0 stays the top row
    // whatever anyone else asked for.
    stbi_set_flip_vertically_on_load_thread(0);
    std::unique_ptr<stbi_uc, StbiFree> pixels(stbi_load_from_memory(p, len, &w, &h, &channels, 4));
    if (!pixels) return bad_format(name, stbi_failure_reason());
    // stb_image decodes some malformed BMP headers to a 0-pixel image and reports success.
    if (w < 1 || h < 1) return bad_format(name, "it decodes to an image without pixels");
    // A format whose header and decoder disagree (e.g. a GIF frame) is held to the limits again.
    if (auto e = check_limits(name, {static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(h)}, limits)) return *e;

    Image image;
    image.width = w;
    image.height = h;
    image.pixels.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    std::memcpy(image.pixels.data(), pixels.get(), image.pixels.size() * sizeof(Rgba8));
    return std::shared_ptr<const Texture>(std::make_shared<const Texture>(std::move(image)));
}

namespace {

// Texture::lod and sample_lod, inlined into Texture::sample: the fragment stage calls sample once per
// pixel, and the calls between these pieces were a fifth of a textured frame.
[[gnu::always_inline]] inline float lod_of(int width, int height, Vec2 duv_dx, Vec2 duv_dy) {
    const Vec2 size{static_cast<float>(width), static_cast<float>(height)};
    const float rho_x = length(duv_dx * size);
    const float rho_y = length(duv_dy * size);
    if (std::isnan(rho_x) || std::isnan(rho_y)) return 0.0f;
    const float rho = std::max(rho_x, rho_y);
    // Not std::log2: the C library's may differ between machines, and so would the mip weights.
    return rho > 0.0f ? portable_log2(rho) : 0.0f;  // +inf for infinite derivatives: the smallest level
}

[[gnu::always_inline]] inline Vec4 sample_at_lod(const Texture& texture, Vec2 uv, float lod, const Sampler& sampler) {
    uv = {finite_or_zero(uv.x), finite_or_zero(uv.y)};
    switch (sampler.filter) {
        case Filter::nearest: return nearest(texture.level(0), uv, sampler) / 255.0f;
        case Filter::bilinear: return bilinear(texture.level(0), uv, sampler) / 255.0f;
        case Filter::trilinear: break;
    }
    const float top = static_cast<float>(texture.level_count() - 1);
    lod = std::isnan(lod) ? 0.0f : clamp(lod, 0.0f, top);
    const float l0 = std::floor(lod);
    const float t = lod - l0;
    const int i0 = static_cast<int>(l0);
    const Vec4 c0 = bilinear(texture.level(i0), uv, sampler);
    if (t == 0.0f) return c0 / 255.0f;  // also the last level, where there is no i0 + 1
    return mix(c0, bilinear(texture.level(i0 + 1), uv, sampler), t) / 255.0f;
}

}  // namespace

float Texture::lod(Vec2 duv_dx, Vec2 duv_dy) const { return lod_of(width(), height(), duv_dx, duv_dy); }

Vec4 Texture::sample(Vec2 uv, Vec2 duv_dx, Vec2 duv_dy, const Sampler& sampler) const {
    // Only trilinear filtering looks at the level of detail; the others skip the log.
    const float l = sampler.filter == Filter::trilinear ? lod_of(width(), height(), duv_dx, duv_dy) : 0.0f;
    return sample_at_lod(*this, uv, l, sampler);
}

Vec4 Texture::sample_lod(Vec2 uv, float lod, const Sampler& sampler) const { return sample_at_lod(*this, uv, lod, sampler); }

}  // namespace facet
