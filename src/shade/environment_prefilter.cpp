// facet shade: the lit mode's environment light computed (facet/environment.hpp). In: radiance over
// the sphere (the built-in studio's function, or an equirectangular image). Out: octahedral maps
// prefiltered for roughness, order-2 SH irradiance, and the split-sum table. Not the per-pixel
// shading (shaders::Pbr), not file reading (environment.cpp); the built-in studio and the split-sum
// table are computed by this file at build time (bake/bake_environment.cpp), not at run time. Only
// +, -, *, /, sqrt, floor and the portable functions (math/portable_trig.hpp,
// facet/math/portable_pow.hpp) are used, so every machine builds the same bits.
#include "shade/environment_prefilter.hpp"

#include <algorithm>
#include <cstring>

#include "facet/math/portable_pow.hpp"
#include "math/portable_trig.hpp"

namespace facet {
namespace {

// ---- octahedral maps ---------------------------------------------------------------------------

std::size_t level_floats(int size) { return static_cast<std::size_t>(size + 2) * static_cast<std::size_t>(size + 2) * 3; }

// A bordered map of its own (the source chain of the prefilter uses these).
struct Map {
    int size = 0;
    std::vector<float> texels;  // (size + 2)^2 RGB, border included
    float* at(int i, int j) { return texels.data() + (static_cast<std::size_t>(j + 1) * (size + 2) + static_cast<std::size_t>(i + 1)) * 3; }
    const float* at(int i, int j) const { return const_cast<Map*>(this)->at(i, j); }
};

Map make_map(int size) { return {size, std::vector<float>(level_floats(size), 0.0f)}; }

// Copies the texels across the folds of the octahedron into the border: past the right edge,
// (size, j) is (size - 1, size - 1 - j); likewise the other edges; each corner is the opposite one.
void fill_border(Map& m) {
    const int s = m.size;
    auto copy = [&](int i, int j, int from_i, int from_j) { std::memcpy(m.at(i, j), m.at(from_i, from_j), 3 * sizeof(float)); };
    for (int k = 0; k < s; ++k) {
        copy(-1, k, 0, s - 1 - k);
        copy(s, k, s - 1, s - 1 - k);
        copy(k, -1, s - 1 - k, 0);
        copy(k, s, s - 1 - k, s - 1);
    }
    copy(-1, -1, s - 1, s - 1);
    copy(s, -1, 0, s - 1);
    copy(-1, s, s - 1, 0);
    copy(s, s, 0, 0);
}

// Bilinear, as Environment::sample_level.
Vec3 sample_map(const Map& m, Vec3 d) {
    const Vec2 uv = octahedral_uv(d);
    const float x = uv.x * static_cast<float>(m.size) - 0.5f, y = uv.y * static_cast<float>(m.size) - 0.5f;
    const float x0 = std::floor(x), y0 = std::floor(y);
    const float tx = x - x0, ty = y - y0;
    const float* a = m.at(static_cast<int>(x0), static_cast<int>(y0));
    const float* b = m.at(static_cast<int>(x0), static_cast<int>(y0) + 1);
    Vec3 c;
    for (int k = 0; k < 3; ++k) {
        const float top = a[k] + (a[3 + k] - a[k]) * tx, bottom = b[k] + (b[3 + k] - b[k]) * tx;
        c[static_cast<std::size_t>(k)] = top + (bottom - top) * ty;
    }
    return c;
}

// The texel's centre direction and its solid angle: an octahedral map's texels span
// dA / |w|^3 steradians, w = (p.x, 1 - |p.x| - |p.z|, p.z) the unnormalized direction (the
// octahedron's faces have unit Jacobian in these coordinates; the folds keep it).
struct Texel {
    Vec3 direction;
    double solid_angle;
};
Texel texel_of(int size, int i, int j) {
    const Vec2 uv{(static_cast<float>(i) + 0.5f) / static_cast<float>(size), (static_cast<float>(j) + 0.5f) / static_cast<float>(size)};
    double px = 2.0 * uv.x - 1, pz = 2.0 * uv.y - 1;
    const double y = 1 - std::fabs(px) - std::fabs(pz);
    if (y < 0) {  // the lower hemisphere: unfolded (the fold itself has a unit Jacobian)
        const double fx = 1 - std::fabs(pz), fz = 1 - std::fabs(px);
        px = px >= 0 ? fx : -fx;
        pz = pz >= 0 ? fz : -fz;
    }
    const double len = std::sqrt(px * px + y * y + pz * pz);
    const double area = (2.0 / size) * (2.0 / size);
    return {octahedral_direction(uv), area / (len * len * len)};
}

// 2x2 box average of the interior, for the prefilter's source chain.
Map downsample(const Map& m) {
    Map out = make_map(m.size / 2);
    for (int j = 0; j < out.size; ++j)
        for (int i = 0; i < out.size; ++i)
            for (int k = 0; k < 3; ++k)
                out.at(i, j)[k] = 0.25f * (m.at(2 * i, 2 * j)[k] + m.at(2 * i + 1, 2 * j)[k] + m.at(2 * i, 2 * j + 1)[k] +
                                           m.at(2 * i + 1, 2 * j + 1)[k]);
    fill_border(out);
    return out;
}

// ---- GGX ---------------------------------------------------------------------------------------

// Hammersley point i of n: (i / n, the radical inverse of i in base 2).
void hammersley(std::uint32_t i, std::uint32_t n, double& u1, double& u2) {
    std::uint32_t b = i;
    b = (b << 16) | (b >> 16);
    b = ((b & 0x55555555u) << 1) | ((b & 0xAAAAAAAAu) >> 1);
    b = ((b & 0x33333333u) << 2) | ((b & 0xCCCCCCCCu) >> 2);
    b = ((b & 0x0F0F0F0Fu) << 4) | ((b & 0xF0F0F0F0u) >> 4);
    b = ((b & 0x00FF00FFu) << 8) | ((b & 0xFF00FF00u) >> 8);
    u1 = static_cast<double>(i) / n;
    u2 = static_cast<double>(b) * 0x1p-32;
}

// A GGX half vector around +Z for alpha = roughness^2, and its cosine with +Z.
struct HalfVector {
    double x, y, z;
};
HalfVector ggx_half_vector(double u1, double u2, double alpha) {
    const double a2 = alpha * alpha;
    const double cos_t = std::sqrt((1 - u2) / (1 + (a2 - 1) * u2));
    const double sin_t = std::sqrt(1 - cos_t * cos_t);
    double s, c;
    portable::sincos(2 * portable::k_pi * u1, s, c);
    return {sin_t * c, sin_t * s, cos_t};
}

double ggx_d(double n_dot_h, double alpha) {
    const double a2 = alpha * alpha, f = n_dot_h * n_dot_h * (a2 - 1) + 1;
    return a2 / (portable::k_pi * f * f);
}

// A tangent frame around unit n.
void frame_of(Vec3 n, Vec3& t, Vec3& b) {
    const Vec3 up = std::fabs(n.y) < 0.999f ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    t = normalize(cross(up, n));
    b = cross(n, t);
}

// One prefiltered level: for each texel direction R (taken as n = v = R, the split-sum
// approximation), the GGX-weighted average of the source over reflected directions, each sample
// read from the source mip whose texels match its share of the lobe (filtered importance sampling,
// Krivanek and Colbert 2008, with Karis' bias of one level).
constexpr std::uint32_t k_prefilter_samples = 48;

void prefilter(const std::vector<Map>& chain, double roughness, Map& out) {
    const double alpha = roughness * roughness;
    struct Sample {
        HalfVector h;
        float weight, lod;
    };
    std::vector<Sample> samples;
    const double texel_solid_angle = 4 * portable::k_pi / (static_cast<double>(chain[0].size) * chain[0].size);
    for (std::uint32_t i = 0; i < k_prefilter_samples; ++i) {
        double u1, u2;
        hammersley(i, k_prefilter_samples, u1, u2);
        const HalfVector h = ggx_half_vector(u1, u2, alpha);
        const double n_dot_l = 2 * h.z * h.z - 1;  // l = reflect(-n, h) with v = n
        if (n_dot_l <= 0) continue;
        const double pdf = ggx_d(h.z, alpha) / 4;  // of l: D (n.h) / (4 v.h), v.h = n.h here
        const double sample_solid_angle = 1 / (k_prefilter_samples * pdf);
        const float lod = std::max(0.0f, 0.5f * detail::portable_log2(static_cast<float>(sample_solid_angle / texel_solid_angle)) + 1.0f);
        samples.push_back({h, static_cast<float>(n_dot_l), lod});
    }
    const float top = static_cast<float>(chain.size() - 1);
    for (int j = 0; j < out.size; ++j)
        for (int i = 0; i < out.size; ++i) {
            const Vec3 r = texel_of(out.size, i, j).direction;
            Vec3 t, b;
            frame_of(r, t, b);
            Vec3 sum{};
            float weight = 0;
            for (const Sample& s : samples) {
                const Vec3 h = normalize(t * static_cast<float>(s.h.x) + b * static_cast<float>(s.h.y) + r * static_cast<float>(s.h.z));
                const Vec3 l = h * (2 * dot(r, h)) - r;
                const float lod = std::min(s.lod, top);
                const float l0 = std::floor(lod), f = lod - l0;
                const auto i0 = static_cast<std::size_t>(l0);
                Vec3 c = sample_map(chain[i0], l);
                if (f > 0) c = c + (sample_map(chain[i0 + 1], l) - c) * f;
                sum = sum + c * s.weight;
                weight += s.weight;
            }
            const Vec3 v = sum / weight;
            std::memcpy(out.at(i, j), &v, sizeof(Vec3));
        }
    fill_border(out);
}

// ---- the built-in studio -----------------------------------------------------------------------

float smoothstep(float edge0, float edge1, float x) {
    const float t = clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
    return t * t * (3 - 2 * t);
}

// A rectangular soft box seen in direction `centre`: half-extents (tangents of the half-angles)
// along `across` and the direction perpendicular to both, with soft edges, radiance `level`.
struct SoftBox {
    Vec3 centre, across;
    float half_width, half_height, level;
};

float soft_box(const SoftBox& box, Vec3 d) {
    const Vec3 c = normalize(box.centre);
    const Vec3 a = normalize(box.across - c * dot(box.across, c)), b = cross(c, a);
    const float along = dot(d, c);
    if (along <= 0) return 0;
    const float x = std::fabs(dot(d, a) / along), y = std::fabs(dot(d, b) / along);
    constexpr float k_edge = 0.08f;  // the width of the boxes' soft edges, in tangent units
    return box.level * smoothstep(box.half_width + k_edge, box.half_width - k_edge, x) *
           smoothstep(box.half_height + k_edge, box.half_height - k_edge, y);
}

// ---- the split-sum table -----------------------------------------------------------------------

// Smith's height-correlated visibility V = G / (4 n.l n.v) for GGX.
double smith_visibility(double n_dot_v, double n_dot_l, double alpha) {
    const double a2 = alpha * alpha;
    const double gv = n_dot_l * std::sqrt(n_dot_v * n_dot_v * (1 - a2) + a2);
    const double gl = n_dot_v * std::sqrt(n_dot_l * n_dot_l * (1 - a2) + a2);
    return 0.5 / (gv + gl);
}

}  // namespace

namespace environment_detail {

// Neutral grey, linear radiance. A dim floor, walls brightening toward a light ceiling, and four
// soft boxes: a large key above-left of the front (from +Z), a broad fill to the right, a panel
// overhead and a strip behind for the rims. Placed so that the front view (facet render) and the
// thumbnails' view from azimuth 35, elevation 25 are both lit from the upper left.
Vec3 studio_radiance(Vec3 d) {
    const float floor_level = 0.08f, wall_level = 0.16f, ceiling_level = 0.22f;
    const float room = d.y < 0 ? wall_level + (floor_level - wall_level) * smoothstep(0.0f, -0.35f, d.y)
                               : wall_level + (ceiling_level - wall_level) * smoothstep(0.1f, 0.8f, d.y);
    static const SoftBox k_boxes[] = {
        {{-0.65f, 0.55f, 0.55f}, {1, 0, 1}, 0.55f, 0.40f, 2.6f},   // key
        {{0.90f, 0.20f, 0.20f}, {0, 0, 1}, 0.70f, 0.45f, 0.9f},    // fill
        {{0.0f, 1.0f, -0.1f}, {1, 0, 0}, 0.45f, 0.45f, 2.2f},      // top
        {{0.25f, 0.35f, -0.95f}, {1, 0, 0}, 0.65f, 0.12f, 2.5f},   // rim strip
    };
    float light = 0;
    for (const SoftBox& b : k_boxes) light += soft_box(b, d);
    const float v = room + light;
    return {v, v, v};
}

// ---- equirectangular images ----------------------------------------------------------------------

// Level 0 from an equirectangular image: each image texel's radiance, weighted by its solid angle,
// averaged into the octahedral texel its centre falls in (a box filter, so a small sun is neither
// lost nor aliased); octahedral texels no image texel falls in (small images) take the image
// bilinearly at their centre.
std::vector<float> equirect_to_octahedral(const float* rgb, int width, int height, int size) {
    std::vector<double> sum(static_cast<std::size_t>(size) * size * 3, 0.0), weight(static_cast<std::size_t>(size) * size, 0.0);
    std::vector<double> sin_phi(static_cast<std::size_t>(width)), cos_phi(static_cast<std::size_t>(width));
    for (int x = 0; x < width; ++x) {
        // The centre column looks toward +X: longitude phi = 2 pi (u - 1/2), d = (cos phi, ., sin phi).
        const double phi = 2 * portable::k_pi * ((x + 0.5) / width - 0.5);
        portable::sincos(phi, sin_phi[static_cast<std::size_t>(x)], cos_phi[static_cast<std::size_t>(x)]);
    }
    auto value = [&](int x, int y, int k) {
        const float v = rgb[(static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x)) * 3 + static_cast<std::size_t>(k)];
        return v > 0 && std::isfinite(v) ? static_cast<double>(v) : 0.0;
    };
    for (int y = 0; y < height; ++y) {
        double sin_t, cos_t;  // theta from +Y (the top row) down
        portable::sincos(portable::k_pi * (y + 0.5) / height, sin_t, cos_t);
        for (int x = 0; x < width; ++x) {
            const Vec3 d{static_cast<float>(sin_t * cos_phi[static_cast<std::size_t>(x)]), static_cast<float>(cos_t),
                         static_cast<float>(sin_t * sin_phi[static_cast<std::size_t>(x)])};
            const Vec2 uv = octahedral_uv(d);
            const int i = std::min(static_cast<int>(uv.x * static_cast<float>(size)), size - 1);
            const int j = std::min(static_cast<int>(uv.y * static_cast<float>(size)), size - 1);
            const std::size_t t = static_cast<std::size_t>(j) * size + static_cast<std::size_t>(i);
            weight[t] += sin_t;
            for (int k = 0; k < 3; ++k) sum[t * 3 + static_cast<std::size_t>(k)] += sin_t * value(x, y, k);
        }
    }
    std::vector<float> out(sum.size());
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const std::size_t t = static_cast<std::size_t>(j) * size + static_cast<std::size_t>(i);
            if (weight[t] > 0) {
                for (int k = 0; k < 3; ++k) out[t * 3 + static_cast<std::size_t>(k)] = static_cast<float>(sum[t * 3 + static_cast<std::size_t>(k)] / weight[t]);
                continue;
            }
            const Vec3 d = texel_of(size, i, j).direction;
            const double u = portable::atan2(d.z, d.x) / (2 * portable::k_pi) + 0.5, v = portable::acos(d.y) / portable::k_pi;
            const double fx = std::clamp(u * width - 0.5, 0.0, width - 1.0), fy = std::clamp(v * height - 0.5, 0.0, height - 1.0);
            const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
            const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
            const double tx = fx - x0, ty = fy - y0;
            for (int k = 0; k < 3; ++k) {
                const double top = value(x0, y0, k) + (value(x1, y0, k) - value(x0, y0, k)) * tx;
                const double bottom = value(x0, y1, k) + (value(x1, y1, k) - value(x0, y1, k)) * tx;
                out[t * 3 + static_cast<std::size_t>(k)] = static_cast<float>(top + (bottom - top) * ty);
            }
        }
    return out;
}

std::vector<float> make_split_sum_table() {
    constexpr std::uint32_t k_samples = 256;
    const int n = k_split_sum_size;
    std::vector<float> table(static_cast<std::size_t>(n) * n * 2);
    for (int j = 0; j < n; ++j) {
        const double roughness = (j + 0.5) / n, alpha = roughness * roughness;
        for (int i = 0; i < n; ++i) {
            const double n_dot_v = (i + 0.5) / n;
            const double vx = std::sqrt(1 - n_dot_v * n_dot_v), vz = n_dot_v;  // v in the xz plane
            double a = 0, b = 0;
            for (std::uint32_t s = 0; s < k_samples; ++s) {
                double u1, u2;
                hammersley(s, k_samples, u1, u2);
                const HalfVector h = ggx_half_vector(u1, u2, alpha);
                const double v_dot_h = vx * h.x + vz * h.z;
                const double lz = 2 * v_dot_h * h.z - vz;  // n.l of l = reflect(-v, h)
                if (lz <= 0 || v_dot_h <= 0) continue;
                // Sampling h by D (n.h): the estimator of the BRDF times n.l over its pdf.
                const double g = smith_visibility(n_dot_v, lz, alpha) * 4 * lz * v_dot_h / h.z;
                const double x = 1 - v_dot_h, fc = x * x * x * x * x;
                a += (1 - fc) * g;
                b += fc * g;
            }
            table[(static_cast<std::size_t>(j) * n + static_cast<std::size_t>(i)) * 2] = static_cast<float>(a / k_samples);
            table[(static_cast<std::size_t>(j) * n + static_cast<std::size_t>(i)) * 2 + 1] = static_cast<float>(b / k_samples);
        }
    }
    return table;
}

}  // namespace environment_detail

Vec3 octahedral_direction(Vec2 uv) {
    float px = uv.x * 2 - 1, pz = uv.y * 2 - 1;
    const float y = 1 - std::fabs(px) - std::fabs(pz);
    if (y < 0) {
        const float fx = 1 - std::fabs(pz), fz = 1 - std::fabs(px);
        px = px >= 0 ? fx : -fx;
        pz = pz >= 0 ? fz : -fz;
    }
    return normalize(Vec3{px, y, pz});
}

std::size_t Environment::lay_out_levels() {
    std::size_t total = 0;
    for (int l = 0; l < k_levels; ++l) {
        levels_[static_cast<std::size_t>(l)] = {k_level_sizes[l], total};
        total += level_floats(k_level_sizes[l]);
    }
    return total;
}

void Environment::build(const std::vector<float>& sharpest) {
    // The source chain: level 0 and its box-filtered halvings down to 1x1.
    std::vector<Map> chain{make_map(k_level_sizes[0])};
    {
        // The interior was given densely; spread it into the bordered rows.
        Map& m = chain[0];
        for (int j = m.size - 1; j >= 0; --j)
            for (int i = m.size - 1; i >= 0; --i)
                std::memcpy(m.at(i, j), sharpest.data() + (static_cast<std::size_t>(j) * m.size + static_cast<std::size_t>(i)) * 3,
                            3 * sizeof(float));
        fill_border(m);
    }
    while (chain.back().size > 1) chain.push_back(downsample(chain.back()));

    // Diffuse: project level 0 onto the SH basis, then convolve with the clamped cosine (its
    // bands' factors pi, 2 pi / 3, pi / 4) and divide by pi.
    // (The texels' solid angles are scaled to sum to 4 pi exactly: the midpoint rule is 1% off.)
    std::array<double, 27> projection{};
    double sphere = 0;
    for (int j = 0; j < chain[0].size; ++j)
        for (int i = 0; i < chain[0].size; ++i) {
            const Texel t = texel_of(chain[0].size, i, j);
            sphere += t.solid_angle;
            const std::array<float, 9> y = sh_basis(t.direction);
            const float* c = chain[0].at(i, j);
            for (std::size_t b = 0; b < 9; ++b)
                for (std::size_t k = 0; k < 3; ++k) projection[b * 3 + k] += static_cast<double>(c[k]) * y[b] * t.solid_angle;
        }
    for (double& p : projection) p *= 4 * portable::k_pi / sphere;
    const double band[3] = {1.0, 2.0 / 3.0, 1.0 / 4.0};  // (pi, 2 pi / 3, pi / 4) / pi
    for (std::size_t b = 0; b < 9; ++b) {
        const double f = band[b == 0 ? 0 : b < 4 ? 1 : 2];
        sh_[b] = {static_cast<float>(projection[b * 3] * f), static_cast<float>(projection[b * 3 + 1] * f),
                  static_cast<float>(projection[b * 3 + 2] * f)};
    }

    texels_.assign(lay_out_levels(), 0.0f);
    std::copy(chain[0].texels.begin(), chain[0].texels.end(), texels_.begin());
    for (int l = 1; l < k_levels; ++l) {
        Map out = make_map(k_level_sizes[l]);
        prefilter(chain, static_cast<double>(l) / (k_levels - 1), out);
        std::copy(out.texels.begin(), out.texels.end(), texels_.begin() + static_cast<std::ptrdiff_t>(levels_[static_cast<std::size_t>(l)].offset));
    }
}

}  // namespace facet
