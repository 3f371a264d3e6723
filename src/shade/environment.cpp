// facet shade: the lit mode's environment lights as the library hands them out (facet/environment.hpp):
// the built-in studio and the split-sum table from the constants computed at build time
// (bake/bake_environment.cpp, so no process spends its start on them), an environment from an
// equirectangular image or a Radiance HDR file. The computing itself is environment_prefilter.cpp;
// the per-pixel shading is shaders::Pbr.
#include "facet/environment.hpp"

#include <stb_image.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "shade/environment_prefilter.hpp"

namespace facet {
namespace {

// ---- Radiance HDR files -------------------------------------------------------------------------

constexpr std::size_t k_max_hdr_bytes = INT_MAX;  // stb_image takes the size as an int

Result<std::vector<unsigned char>> read_hdr_file(const std::string& path) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
    if (!file) return Error{ErrorCode::io, path + ": cannot open: " + std::strerror(errno)};
    std::vector<unsigned char> bytes;
    unsigned char chunk[1 << 16];
    for (;;) {
        const std::size_t n = std::fread(chunk, 1, sizeof(chunk), file.get());
        bytes.insert(bytes.end(), chunk, chunk + n);
        if (bytes.size() > k_max_hdr_bytes) return Error{ErrorCode::limit_exceeded, path + ": the file is larger than 2 GiB"};
        if (n < sizeof(chunk)) break;
    }
    // A directory opens on Linux; reading it is what fails (EISDIR).
    if (std::ferror(file.get())) return Error{ErrorCode::io, path + ": cannot read: " + std::strerror(errno)};
    return bytes;
}

// stb_image 2.27 decodes a Radiance file whose pixels are cut short by reading zeros past its end
// (a quietly black image), and loops forever on a run-length count of 0. So the pixel data is walked
// first, as stb_image will read it (flat RGBE, or scanlines of four run-length coded channels): why
// it is unreadable, or null.
const char* check_rgbe_data(const std::vector<unsigned char>& bytes, int width, int height) {
    // The header ends with an empty line, then the resolution line ("-Y h +X w").
    std::size_t at = 0;
    for (std::size_t i = 0; i + 1 < bytes.size(); ++i)
        if (bytes[i] == '\n' && bytes[i + 1] == '\n') {
            at = i + 2;
            break;
        }
    while (at < bytes.size() && bytes[at] != '\n') ++at;
    if (at++ >= bytes.size()) return "no pixel data";
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    const auto flat = [&]() -> const char* { return bytes.size() - at >= pixels * 4 ? nullptr : "the pixel data is cut short"; };
    if (width < 8 || width >= 32768) return flat();
    for (int y = 0; y < height; ++y) {
        if (bytes.size() - at < 4) return "the pixel data is cut short";
        const unsigned char* s = bytes.data() + at;
        if (s[0] != 2 || s[1] != 2 || (s[2] & 0x80)) {
            if (y == 0) return flat();  // not run-length coded: flat pixels from here
            return "a scanline that is not run-length coded after one that is";
        }
        if ((s[2] << 8 | s[3]) != width) return "a scanline of the wrong length";
        at += 4;
        for (int channel = 0; channel < 4; ++channel)
            for (int x = 0; x < width;) {
                if (at >= bytes.size()) return "the pixel data is cut short";
                int count = bytes[at++];
                const bool run = count > 128;
                if (run) count -= 128;
                if (count == 0 || count > width - x) return "a bad run length";
                const std::size_t need = run ? 1 : static_cast<std::size_t>(count);
                if (bytes.size() - at < need) return "the pixel data is cut short";
                at += need;
                x += count;
            }
    }
    return nullptr;
}

}  // namespace

std::shared_ptr<const Environment> Environment::studio() {
    static const std::shared_ptr<const Environment> e = [] {
        const environment_detail::BakedStudio baked = environment_detail::baked_studio();
        std::shared_ptr<Environment> s(new Environment());
        s->lay_out_levels();
        s->baked_ = baked.texels;
        s->baked_count_ = baked.texel_count;
        for (std::size_t b = 0; b < 9; ++b) s->sh_[b] = {baked.sh[b * 3], baked.sh[b * 3 + 1], baked.sh[b * 3 + 2]};
        return std::shared_ptr<const Environment>(std::move(s));
    }();
    return e;
}

std::shared_ptr<const Environment> Environment::from_equirect(const float* rgb, int width, int height) {
    if (!rgb || width < 1 || height < 1)
        throw FacetError(Error{ErrorCode::invalid_argument, "Environment::from_equirect: the image is empty (" +
                                                                std::to_string(width) + "x" + std::to_string(height) + ")"});
    std::shared_ptr<Environment> e(new Environment());
    e->build(environment_detail::equirect_to_octahedral(rgb, width, height, k_level_sizes[0]));
    return e;
}

Result<std::shared_ptr<const Environment>> Environment::load_hdr(const std::string& path, std::size_t max_pixels) {
    Result<std::vector<unsigned char>> bytes = read_hdr_file(path);
    if (!bytes) return bytes.error();
    const auto* p = bytes->data();
    const int len = static_cast<int>(bytes->size());
    if (bytes->empty() || !stbi_is_hdr_from_memory(p, len))
        return Error{ErrorCode::bad_format, path + ": not a Radiance HDR image (expected a file starting with #?RADIANCE or #?RGBE)"};
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_memory(p, len, &w, &h, &channels))
        return Error{ErrorCode::bad_format, path + ": not a readable HDR image (" + std::string(stbi_failure_reason()) + ")"};
    if (w < 1 || h < 1 || static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > max_pixels)
        return Error{ErrorCode::limit_exceeded, path + ": the image is " + std::to_string(w) + "x" + std::to_string(h) +
                                                    ", over the limit of " + std::to_string(max_pixels) + " pixels"};
    if (const char* why = check_rgbe_data(*bytes, w, h))
        return Error{ErrorCode::bad_format, path + ": not a readable HDR image (" + why + ")"};
    stbi_set_flip_vertically_on_load_thread(0);
    struct Free {
        void operator()(float* f) const { stbi_image_free(f); }
    };
    std::unique_ptr<float, Free> rgb(stbi_loadf_from_memory(p, len, &w, &h, &channels, 3));
    if (!rgb) return Error{ErrorCode::bad_format, path + ": not a readable HDR image (" + std::string(stbi_failure_reason()) + ")"};
    return from_equirect(rgb.get(), w, h);
}

const std::vector<float>& split_sum_table() {
    static const std::vector<float> table = [] {
        const float* t = environment_detail::baked_studio().split_sum;
        return std::vector<float>(t, t + std::size_t{k_split_sum_size} * k_split_sum_size * 2);
    }();
    return table;
}

Vec2 split_sum(float n_dot_v, float roughness) {
    const std::vector<float>& t = split_sum_table();
    const int n = k_split_sum_size;
    const float top = static_cast<float>(n - 1);
    auto coordinate = [&](float v) {
        const float x = v * static_cast<float>(n) - 0.5f;
        return x > 0 ? (x < top ? x : top) : 0.0f;  // NaN: 0
    };
    const float x = coordinate(n_dot_v), y = coordinate(roughness);
    const float x0 = std::floor(x), y0 = std::floor(y);
    const float tx = x - x0, ty = y - y0;
    const int i0 = static_cast<int>(x0), j0 = static_cast<int>(y0);
    const int i1 = std::min(i0 + 1, n - 1), j1 = std::min(j0 + 1, n - 1);
    auto at = [&](int i, int j, int k) { return t[(static_cast<std::size_t>(j) * n + static_cast<std::size_t>(i)) * 2 + static_cast<std::size_t>(k)]; };
    Vec2 r;
    for (int k = 0; k < 2; ++k) {
        const float top_row = at(i0, j0, k) + (at(i1, j0, k) - at(i0, j0, k)) * tx;
        const float bottom_row = at(i0, j1, k) + (at(i1, j1, k) - at(i0, j1, k)) * tx;
        r[static_cast<std::size_t>(k)] = top_row + (bottom_row - top_row) * ty;
    }
    return r;
}

}  // namespace facet
