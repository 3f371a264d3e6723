// facet shade: the SIMD visible-pixel pass of the lit mode's shaders::Pbr and shaders::PbrNormalMapped
// (shade/visible_simd-inl.h has the shared tile loop and what the kernels compute), compiled once per
// ISA by Highway. Every step is the scalar fragment()'s (shaders.hpp, environment.hpp,
// tone_mapping.hpp) in lanes, operation for operation: the environment's octahedral maps, the
// split-sum table and the SH irradiance read with gathers and the same bilinear arithmetic, the
// tone mappers and sRGB's portable_pow in lanes, texture maps with Texture::sample's arithmetic in
// lanes (bilinear and trilinear, untransformed; portable_log2 of the level of detail in lanes; the
// other maps by the scalar sampler, lane by lane); the ...Masked shaders, which discard, take the
// one-pass order and have no kernel.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shade/visible_simd_pbr.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include "facet/shaders.hpp"
#include "shade/visible_simd-inl.h"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using VI = hn::Vec<DI>;

// a > 0 ? (a < hi ? a : hi) : 0, the clamps of environment.hpp (NaN to 0).
HWY_INLINE VF clamp_zero_to(VF a, float hi) {
    const DF df;
    return hn::IfThenElse(hn::Gt(a, hn::Zero(df)), hn::IfThenElse(hn::Lt(a, hn::Set(df, hi)), a, hn::Set(df, hi)),
                          hn::Zero(df));
}

HWY_INLINE Vec3Lanes add(const Vec3Lanes& a, const Vec3Lanes& b) {
    return {hn::Add(a.x, b.x), hn::Add(a.y, b.y), hn::Add(a.z, b.z)};
}
HWY_INLINE Vec3Lanes sub(const Vec3Lanes& a, const Vec3Lanes& b) {
    return {hn::Sub(a.x, b.x), hn::Sub(a.y, b.y), hn::Sub(a.z, b.z)};
}
HWY_INLINE Vec3Lanes mul(const Vec3Lanes& a, const Vec3Lanes& b) {
    return {hn::Mul(a.x, b.x), hn::Mul(a.y, b.y), hn::Mul(a.z, b.z)};
}
HWY_INLINE Vec3Lanes mul(const Vec3Lanes& a, VF s) { return {hn::Mul(a.x, s), hn::Mul(a.y, s), hn::Mul(a.z, s)}; }
HWY_INLINE Vec3Lanes splat3(float v) {
    const DF df;
    return {hn::Set(df, v), hn::Set(df, v), hn::Set(df, v)};
}

// ---- environment.hpp in lanes --------------------------------------------------------------------

// octahedral_uv
HWY_INLINE void octahedral_uv(const Vec3Lanes& d, VF& u, VF& v) {
    const DF df;
    const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), half = hn::Set(df, 0.5f);
    const VF l1 = hn::Add(hn::Add(hn::Abs(d.x), hn::Abs(d.y)), hn::Abs(d.z));
    VF px = hn::Div(d.x, l1), pz = hn::Div(d.z, l1);
    const VF fx = hn::Sub(one, hn::Abs(pz)), fz = hn::Sub(one, hn::Abs(px));
    const MF lower = hn::Lt(d.y, zero);
    px = hn::IfThenElse(lower, hn::IfThenElse(hn::Ge(px, zero), fx, hn::Neg(fx)), px);
    pz = hn::IfThenElse(lower, hn::IfThenElse(hn::Ge(pz, zero), fz, hn::Neg(fz)), pz);
    const MF centre = hn::Not(hn::Gt(l1, zero));
    u = hn::IfThenElse(centre, half, hn::Add(hn::Mul(px, half), half));
    v = hn::IfThenElse(centre, half, hn::Add(hn::Mul(pz, half), half));
}

// t[i] and t[i + 1] for each lane's index i: one 64-bit gather per pair of floats instead of two
// 32-bit ones (half the elements to fetch), split into the two floats by even and odd lanes. The
// same bits as GatherIndex of i and i + 1; t[i + 1] is always one the caller reads.
HWY_INLINE void gather_pair(const float* t, VI i, VF& first, VF& second) {
    const DF df;
#if HWY_TARGET == HWY_SCALAR
    const DI di;
    first = hn::GatherIndex(df, t, i), second = hn::GatherIndex(df, t, hn::Add(i, hn::Set(di, 1)));
#else
    const hn::Repartition<std::int64_t, DF> d64;
    const hn::Half<DI> dh;
    const auto* pairs = reinterpret_cast<const std::int64_t*>(t);  // read by bytes: any float is a start
    const auto bytes = [&](hn::Vec<hn::Half<DI>> half) { return hn::ShiftLeft<2>(hn::PromoteTo(d64, half)); };
    const VF lo = hn::BitCast(df, hn::GatherOffset(d64, pairs, bytes(hn::LowerHalf(dh, i))));
    const VF hi = hn::BitCast(df, hn::GatherOffset(d64, pairs, bytes(hn::UpperHalf(dh, i))));
    first = hn::ConcatEven(df, hi, lo), second = hn::ConcatOdd(df, hi, lo);
#endif
}

// The environment's mip levels as sample_level reads them (each one's size and offset), taken once
// per tile.
struct EnvironmentLevels {
    HWY_ALIGN std::int32_t sizes[8] = {}, offsets[8] = {};
    explicit EnvironmentLevels(const Environment* env) {
        for (int i = 0; env && i < Environment::k_levels; ++i) {
            sizes[i] = env->level(i).size;
            offsets[i] = static_cast<std::int32_t>(env->level(i).offset);
        }
    }
};

// Environment::sample_level for lanes whose levels are `level` (each lane its own), or all
// `uniform` when that is not negative (the same values, without the gathers).
// `u`, `v`: octahedral_uv of the direction (the same for both levels of a lookup). `Grey`: the
// environment's texels are grey (grey_studio), so the red channel's result is each channel's.
template <bool Grey>
HWY_INLINE Vec3Lanes sample_level(const Environment& env, const EnvironmentLevels& levels, VI level, VF u, VF v,
                                  int uniform) {
    const DF df;
    const DI di;
    const VI size = uniform >= 0 ? hn::Set(di, levels.sizes[uniform]) : hn::GatherIndex(di, levels.sizes, level);
    const VI offset = uniform >= 0 ? hn::Set(di, levels.offsets[uniform]) : hn::GatherIndex(di, levels.offsets, level);
    const VF fsize = hn::ConvertTo(df, size), half = hn::Set(df, 0.5f);
    const VF x = hn::Sub(hn::Mul(u, fsize), half), y = hn::Sub(hn::Mul(v, fsize), half);
    const VF x0 = hn::Floor(x), y0 = hn::Floor(y);
    const VF tx = hn::Sub(x, x0), ty = hn::Sub(y, y0);
    const VI one = hn::Set(di, 1), three = hn::Set(di, 3);
    const VI stride = hn::Add(size, hn::Set(di, 2));
    const VI texel = hn::Add(hn::Mul(hn::Add(hn::ConvertTo(di, y0), one), stride), hn::Add(hn::ConvertTo(di, x0), one));
    const VI a = hn::Add(offset, hn::Mul(texel, three));
    const VI b = hn::Add(a, hn::Mul(stride, three));
    const float* t = env.texels().data();
    if constexpr (Grey) {
        // A texel's blue is its red (grey), and the next texel's red follows it: the two reds of a
        // row are the float pair at a + 2, one 64-bit gather.
        const VI two = hn::Set(di, 2);
        VF a0, a1, b0, b1;
        gather_pair(t, hn::Add(a, two), a0, a1);
        gather_pair(t, hn::Add(b, two), b0, b1);
        const VF top = hn::Add(a0, hn::Mul(hn::Sub(a1, a0), tx));
        const VF bottom = hn::Add(b0, hn::Mul(hn::Sub(b1, b0), tx));
        const VF c = hn::Add(top, hn::Mul(hn::Sub(bottom, top), ty));
        return {c, c, c};
    }
    // Each row's two texels are six floats in a row (RGB, RGB): three pairs.
    VF row_a[6], row_b[6];
    for (int k = 0; k < 6; k += 2) {
        const VI kk = hn::Set(di, k);
        gather_pair(t, hn::Add(a, kk), row_a[k], row_a[k + 1]);
        gather_pair(t, hn::Add(b, kk), row_b[k], row_b[k + 1]);
    }
    VF c[3];
    for (int k = 0; k < 3; ++k) {
        const VF a0 = row_a[k], a1 = row_a[k + 3], b0 = row_b[k], b1 = row_b[k + 3];
        const VF top = hn::Add(a0, hn::Mul(hn::Sub(a1, a0), tx));
        const VF bottom = hn::Add(b0, hn::Mul(hn::Sub(b1, b0), tx));
        c[k] = hn::Add(top, hn::Mul(hn::Sub(bottom, top), ty));
    }
    return {c[0], c[1], c[2]};
}

// Environment::specular; `uniform_lod`: every lane's lod is the same (a material's roughness).
template <bool Grey>
HWY_INLINE Vec3Lanes specular(const Environment& env, const EnvironmentLevels& levels, const Vec3Lanes& r, VF lod,
                              bool uniform_lod) {
    const DF df;
    const DI di;
    constexpr int top = Environment::k_levels - 1;
    lod = clamp_zero_to(lod, static_cast<float>(top));
    const VF l0 = hn::Floor(lod);
    const VF t = hn::Sub(lod, l0);
    const VI i0 = hn::ConvertTo(di, l0);
    const int u0 = uniform_lod ? hn::GetLane(i0) : -1;
    VF u, v;
    octahedral_uv(r, u, v);
    const Vec3Lanes c0 = sample_level<Grey>(env, levels, i0, u, v, u0);
    const MF blend = hn::Ne(t, hn::Zero(df));
    if (hn::AllFalse(df, blend)) return c0;
    const Vec3Lanes c1 =
        sample_level<Grey>(env, levels, hn::Min(hn::Add(i0, hn::Set(di, 1)), hn::Set(di, top)), u, v, uniform_lod ? std::min(u0 + 1, top) : -1);
    const Vec3Lanes mixed = add(c0, mul(sub(c1, c0), t));
    return select(blend, mixed, c0);
}

// Environment::diffuse: the SH sum over sh_basis, clamped at 0 (`Grey`: the coefficients are grey).
template <bool Grey>
HWY_INLINE Vec3Lanes diffuse(const Environment& env, const Vec3Lanes& d) {
    const DF df;
    auto k = [&](float c) { return hn::Set(df, c); };
    const VF y[9] = {k(0.282094792f),
                     hn::Mul(k(0.488602512f), d.y),
                     hn::Mul(k(0.488602512f), d.z),
                     hn::Mul(k(0.488602512f), d.x),
                     hn::Mul(hn::Mul(k(1.092548431f), d.x), d.y),
                     hn::Mul(hn::Mul(k(1.092548431f), d.y), d.z),
                     hn::Mul(k(0.315391565f), hn::Sub(hn::Mul(hn::Mul(k(3), d.z), d.z), k(1))),
                     hn::Mul(hn::Mul(k(1.092548431f), d.x), d.z),
                     hn::Mul(k(0.546274215f), hn::Sub(hn::Mul(d.x, d.x), hn::Mul(d.y, d.y)))};
    const auto& sh = env.diffuse_sh();
    if constexpr (Grey) {
        VF c = hn::Zero(df);
        for (std::size_t i = 0; i < 9; ++i) c = hn::Add(c, hn::Mul(hn::Set(df, sh[i].x), y[i]));
        c = max_zero(c);
        return {c, c, c};
    }
    Vec3Lanes c{hn::Zero(df), hn::Zero(df), hn::Zero(df)};
    for (std::size_t i = 0; i < 9; ++i) c = add(c, mul(splat(sh[i]), y[i]));
    return {max_zero(c.x), max_zero(c.y), max_zero(c.z)};
}

// The split-sum table's A and B apart, each row of k_split_sum_size entries in a row of floats.
struct SplitSumRows {
    static constexpr std::size_t k_entries = std::size_t{k_split_sum_size} * k_split_sum_size;
    HWY_ALIGN float a[k_entries], b[k_entries];
};
HWY_NOINLINE const SplitSumRows& split_sum_rows() {
    static const SplitSumRows rows = [] {
        SplitSumRows r;
        const float* table = split_sum_table().data();
        for (std::size_t e = 0; e < SplitSumRows::k_entries; ++e) r.a[e] = table[2 * e], r.b[e] = table[2 * e + 1];
        return r;
    }();
    return rows;
}

// row[i] for each lane's i in [0, 2 lanes): the row's two vectors looked up within and the lanes
// taken from the one that holds i (permutes instead of a gather).
HWY_INLINE VF lookup_in_two_vectors(const float* row, VI i) {
    const DF df;
    const DI di;
    constexpr int lanes = static_cast<int>(hn::MaxLanes(DF()));
    const auto within = hn::IndicesFromVec(df, hn::And(i, hn::Set(di, lanes - 1)));
    const VF low = hn::TableLookupLanes(hn::Load(df, row), within);
    const VF high = hn::TableLookupLanes(hn::Load(df, row + lanes), within);
    return hn::IfThenElse(hn::RebindMask(df, hn::Gt(i, hn::Set(di, lanes - 1))), high, low);
}

// split_sum: {A, B}. `uniform_roughness`: every lane's roughness is the same (a material's), and so
// are the two rows read: where a row is two vectors (16 lanes), its entries are found by permutes.
HWY_INLINE void split_sum(VF n_dot_v, VF roughness, bool uniform_roughness, VF& a, VF& b) {
    const DF df;
    const DI di;
    const float* table = split_sum_table().data();
    constexpr int n = k_split_sum_size;
    auto coordinate = [&](VF v) {
        return clamp_zero_to(hn::Sub(hn::Mul(v, hn::Set(df, static_cast<float>(n))), hn::Set(df, 0.5f)), static_cast<float>(n - 1));
    };
    const VF x = coordinate(n_dot_v), y = coordinate(roughness);
    const VF x0 = hn::Floor(x), y0 = hn::Floor(y);
    const VF tx = hn::Sub(x, x0), ty = hn::Sub(y, y0);
    const VI i0 = hn::ConvertTo(di, x0), j0 = hn::ConvertTo(di, y0);
    const VI last = hn::Set(di, n - 1), one = hn::Set(di, 1), width = hn::Set(di, n), two = hn::Set(di, 2);
    const VI i1 = hn::Min(hn::Add(i0, one), last), j1 = hn::Min(hn::Add(j0, one), last);
    // A texel's A and B are a pair of floats.
    VF p00[2], p10[2], p01[2], p11[2];
    bool looked_up = false;
    if constexpr (hn::MaxLanes(DF()) * 2 == n) {
        if (uniform_roughness) {
            const SplitSumRows& rows = split_sum_rows();
            const std::size_t row0 = static_cast<std::size_t>(hn::GetLane(j0)) * n;
            const std::size_t row1 = static_cast<std::size_t>(hn::GetLane(j1)) * n;
            auto at = [&](VI i, std::size_t row, VF* ab) {
                ab[0] = lookup_in_two_vectors(rows.a + row, i), ab[1] = lookup_in_two_vectors(rows.b + row, i);
            };
            at(i0, row0, p00), at(i1, row0, p10), at(i0, row1, p01), at(i1, row1, p11);
            looked_up = true;
        }
    }
    if (!looked_up) {
        auto at = [&](VI i, VI j, VF* ab) { gather_pair(table, hn::Mul(hn::Add(hn::Mul(j, width), i), two), ab[0], ab[1]); };
        at(i0, j0, p00), at(i1, j0, p10), at(i0, j1, p01), at(i1, j1, p11);
    }
    VF r[2];
    for (int k = 0; k < 2; ++k) {
        const VF top_row = hn::Add(p00[k], hn::Mul(hn::Sub(p10[k], p00[k]), tx));
        const VF bottom_row = hn::Add(p01[k], hn::Mul(hn::Sub(p11[k], p01[k]), tx));
        r[k] = hn::Add(top_row, hn::Mul(hn::Sub(bottom_row, top_row), ty));
    }
    a = r[0], b = r[1];
}

// ---- tone_mapping.hpp in lanes ---------------------------------------------------------------------

HWY_INLINE VF min3(VF a, VF b, VF c) {
    return hn::IfThenElse(hn::Lt(a, b), hn::IfThenElse(hn::Lt(a, c), a, c), hn::IfThenElse(hn::Lt(b, c), b, c));
}
HWY_INLINE VF max3(VF a, VF b, VF c) {
    return hn::IfThenElse(hn::Gt(a, b), hn::IfThenElse(hn::Gt(a, c), a, c), hn::IfThenElse(hn::Gt(b, c), b, c));
}

HWY_INLINE Vec3Lanes tone_map_pbr_neutral(Vec3Lanes c) {
    const DF df;
    constexpr float k_start_compression = 0.8f - 0.04f, k_desaturation = 0.15f;
    constexpr float d = 1 - k_start_compression;
    const VF x = min3(c.x, c.y, c.z);
    const VF offset = hn::IfThenElse(hn::Lt(x, hn::Set(df, 0.08f)), hn::Sub(x, hn::Mul(hn::Mul(hn::Set(df, 6.25f), x), x)),
                                     hn::Set(df, 0.04f));
    c = sub(c, {offset, offset, offset});
    const VF peak = max3(c.x, c.y, c.z);
    const MF low = hn::Lt(peak, hn::Set(df, k_start_compression));
    if (hn::AllTrue(df, low)) return c;
    const VF one = hn::Set(df, 1.0f);
    const VF new_peak = hn::Sub(one, hn::Div(hn::Set(df, d * d), hn::Sub(hn::Add(peak, hn::Set(df, d)), hn::Set(df, k_start_compression))));
    const Vec3Lanes scaled = mul(c, hn::Div(new_peak, peak));
    const VF g = hn::Sub(one, hn::Div(one, hn::Add(hn::Mul(hn::Set(df, k_desaturation), hn::Sub(peak, new_peak)), one)));
    const Vec3Lanes mapped = add(scaled, mul(sub({new_peak, new_peak, new_peak}, scaled), g));
    return select(low, c, mapped);
}

HWY_INLINE VF aces_rrt_odt_fit(VF v) {
    const DF df;
    const VF a = hn::Sub(hn::Mul(v, hn::Add(v, hn::Set(df, 0.0245786f))), hn::Set(df, 0.000090537f));
    const VF b = hn::Add(hn::Mul(v, hn::Add(hn::Mul(hn::Set(df, 0.983729f), v), hn::Set(df, 0.4329510f))), hn::Set(df, 0.238081f));
    return hn::Div(a, b);
}

HWY_INLINE Vec3Lanes tone_map_aces(Vec3Lanes c) {
    const DF df;
    c = mul(c, hn::Set(df, 1 / 0.6f));
    auto row = [&](float p, float q, float r) {
        return hn::Add(hn::Add(hn::Mul(hn::Set(df, p), c.x), hn::Mul(hn::Set(df, q), c.y)), hn::Mul(hn::Set(df, r), c.z));
    };
    const VF ix = row(0.59719f, 0.35458f, 0.04823f), iy = row(0.07600f, 0.90834f, 0.01566f), iz = row(0.02840f, 0.13383f, 0.83777f);
    const VF fx = aces_rrt_odt_fit(ix), fy = aces_rrt_odt_fit(iy), fz = aces_rrt_odt_fit(iz);
    // 1.60475 f.x - 0.53108 f.y - 0.07367 f.z, ...: subtractions as the scalar code writes them.
    auto out = [&](float p, float q, float r, bool q_negative, bool r_negative, bool p_negative) {
        VF s = hn::Mul(hn::Set(df, p), fx);
        if (p_negative) s = hn::Neg(s);
        const VF t = hn::Mul(hn::Set(df, q), fy), u = hn::Mul(hn::Set(df, r), fz);
        s = q_negative ? hn::Sub(s, t) : hn::Add(s, t);
        s = r_negative ? hn::Sub(s, u) : hn::Add(s, u);
        // clamp(v, 0, 1): v < 0 ? 0 : (v > 1 ? 1 : v)
        const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f);
        return hn::IfThenElse(hn::Lt(s, zero), zero, hn::IfThenElse(hn::Gt(s, one), one, s));
    };
    return {out(1.60475f, 0.53108f, 0.07367f, true, true, false), out(0.10208f, 1.10813f, 0.00605f, false, true, true),
            out(0.00327f, 0.07276f, 1.07602f, true, false, true)};
}

HWY_INLINE VF linear_to_srgb(VF c) {
    const DF df;
    c = clamp_zero_to(c, 1.0f);
    const VF curve = hn::Sub(hn::Mul(hn::Set(df, 1.055f), portable_pow(c, 1 / 2.4f)), hn::Set(df, 0.055f));
    return hn::IfThenElse(hn::Le(c, hn::Set(df, 0.0031308f)), hn::Mul(hn::Set(df, 12.92f), c), curve);
}

HWY_INLINE VF srgb_to_linear(VF c) {
    const DF df;
    const VF curve = portable_pow(hn::Div(hn::Add(c, hn::Set(df, 0.055f)), hn::Set(df, 1.055f)), 2.4f);
    return hn::IfThenElse(hn::Le(c, hn::Set(df, 0.04045f)), hn::Div(c, hn::Set(df, 12.92f)), curve);
}

// shaders::detail::display
HWY_INLINE Vec3Lanes display(const Vec3Lanes& radiance, const PbrUniforms& p) {
    const DF df;
    Vec3Lanes t = mul(radiance, hn::Set(df, p.exposure));
    switch (p.tone_mapping) {
        case ToneMapping::neutral: t = tone_map_pbr_neutral(t); break;
        case ToneMapping::aces: t = tone_map_aces(t); break;
        case ToneMapping::linear: break;
    }
    return {linear_to_srgb(t.x), linear_to_srgb(t.y), linear_to_srgb(t.z)};
}

// Whether `env` is the built-in studio and its texels and SH are grey (each channel's bits the
// same), which they are: looked at once. Only the studio, which lives as long as the process: an
// environment of the caller's could be freed and another built at its address.
inline bool grey_studio(const Environment* env) {
    static const Environment* const studio = Environment::studio().get();
    static const bool grey_texels_and_sh = [] {
        const std::span<const float> t = studio->texels();
        for (std::size_t i = 0; i + 2 < t.size(); i += 3)
            if (!grey(Vec3{t[i], t[i + 1], t[i + 2]})) return false;
        for (const Vec3& c : studio->diffuse_sh())
            if (!grey(c)) return false;
        return true;
    }();
    return env == studio && grey_texels_and_sh;
}

// ---- Texture::sample in lanes (texture.cpp), trilinear ----------------------------------------------

// One level's bilinear filter, Texture's bilinear(): footprint() on each axis (the coordinate
// folded by its wrap, the two texels either side and the weight of the second), the four texels'
// channels as floats 0..255, mixed along x and then y.
struct LevelLanes {
    const std::uint32_t* texels;  // Rgba8, red in the low byte
    int width, height;

    static HWY_INLINE VF wrap_coord(VF u, Wrap wrap) {
        const DF df;
        switch (wrap) {
            case Wrap::repeat: return hn::Sub(u, hn::Floor(u));
            case Wrap::clamp: return clamp_to(u, 0.0f, 1.0f);
            case Wrap::mirror: {
                const VF t = hn::Sub(u, hn::Mul(hn::Set(df, 2.0f), hn::Floor(hn::Mul(u, hn::Set(df, 0.5f)))));
                return hn::IfThenElse(hn::Gt(t, hn::Set(df, 1.0f)), hn::Sub(hn::Set(df, 2.0f), t), t);
            }
        }
        return hn::Zero(df);
    }
    // clamp(): v < lo ? lo : (v > hi ? hi : v)
    static HWY_INLINE VF clamp_to(VF v, float lo, float hi) {
        const DF df;
        return hn::IfThenElse(hn::Lt(v, hn::Set(df, lo)), hn::Set(df, lo), hn::IfThenElse(hn::Gt(v, hn::Set(df, hi)), hn::Set(df, hi), v));
    }
    static HWY_INLINE VI wrap_index(VI i, int size, Wrap wrap) {
        const DI di;
        const VI last = hn::Set(di, size - 1);
        if (wrap == Wrap::repeat)
            return hn::IfThenElse(hn::Lt(i, hn::Zero(di)), last, hn::IfThenElse(hn::Lt(i, hn::Set(di, size)), i, hn::Zero(di)));
        return hn::Min(hn::Max(i, hn::Zero(di)), last);
    }
    static HWY_INLINE VF footprint(VF u, int size, Wrap wrap, VI& i0, VI& i1) {
        const DF df;
        const DI di;
        const VF x = hn::Sub(hn::Mul(wrap_coord(u, wrap), hn::Set(df, static_cast<float>(size))), hn::Set(df, 0.5f));
        const VF x0 = hn::Floor(x);
        const VI first = hn::ConvertTo(di, x0);
        i0 = wrap_index(first, size, wrap), i1 = wrap_index(hn::Add(first, hn::Set(di, 1)), size, wrap);
        return hn::Sub(x, x0);
    }
    HWY_INLINE ColourLanes texel(VI x, VI y) const {
        const DF df;
        const DI di;
        const DU du;
        const auto packed = hn::GatherIndex(du, texels, hn::Add(hn::Mul(y, hn::Set(di, width)), x));
        auto channel = [&](int shift) {
            return hn::ConvertTo(df, hn::BitCast(di, hn::And(hn::ShiftRightSame(packed, shift), hn::Set(du, 0xffu))));
        };
        return {channel(0), channel(8), channel(16), channel(24)};
    }
    static HWY_INLINE ColourLanes mix(const ColourLanes& a, const ColourLanes& b, VF t) {
        auto m = [&](VF p, VF q) { return hn::Add(p, hn::Mul(hn::Sub(q, p), t)); };
        return {m(a.r, b.r), m(a.g, b.g), m(a.b, b.b), m(a.a, b.a)};
    }
    HWY_INLINE ColourLanes operator()(VF u, VF v, const Sampler& s) const {
        VI x0, x1, y0, y1;
        const VF tx = footprint(u, width, s.wrap_u, x0, x1), ty = footprint(v, height, s.wrap_v, y0, y1);
        const ColourLanes top = mix(texel(x0, y0), texel(x1, y0), tx);
        const ColourLanes bottom = mix(texel(x0, y1), texel(x1, y1), tx);
        return mix(top, bottom, ty);
    }
};

HWY_INLINE LevelLanes level_lanes(const Texture& t, int i) {
    const Image& l = t.level(i);
    return {reinterpret_cast<const std::uint32_t*>(l.pixels.data()), l.width, l.height};
}

// Texture::sample with Filter::bilinear or trilinear for the `visible` lanes (the others 0), in
// sample_at_lod's operations: the level of detail of lod_of (portable_log2 in lanes), clamped, its
// floor's level and the next mixed by its fraction, divided by 255. The lanes are taken one level at
// a time (a vector's pixels mostly share one).
HWY_INLINE ColourLanes sample_filtered(const Texture& texture, const Sampler& s, VF u, VF v, VF ux, VF vx, VF uy,
                                       VF vy, MF visible) {
    const DF df;
    const DI di;
    constexpr int lanes = static_cast<int>(hn::MaxLanes(DF()));
    u = hn::IfThenElseZero(hn::IsFinite(u), u), v = hn::IfThenElseZero(hn::IsFinite(v), v);
    const VF k255 = hn::Set(df, 255.0f);
    if (s.filter == Filter::bilinear) {
        const ColourLanes c = level_lanes(texture, 0)(u, v, s);
        return {hn::IfThenElseZero(visible, hn::Div(c.r, k255)), hn::IfThenElseZero(visible, hn::Div(c.g, k255)),
                hn::IfThenElseZero(visible, hn::Div(c.b, k255)), hn::IfThenElseZero(visible, hn::Div(c.a, k255))};
    }
    const VF w = hn::Set(df, static_cast<float>(texture.width())), h = hn::Set(df, static_cast<float>(texture.height()));
    auto length = [&](VF du, VF dv) {
        const VF a = hn::Mul(du, w), b = hn::Mul(dv, h);
        return hn::Sqrt(hn::Add(hn::Mul(a, a), hn::Mul(b, b)));
    };
    const VF rho_x = length(ux, vx), rho_y = length(uy, vy);
    const MF nan = hn::Or(hn::IsNaN(rho_x), hn::IsNaN(rho_y));
    const VF rho = hn::IfThenElse(hn::Lt(rho_x, rho_y), rho_y, rho_x);
    const MF logged = hn::AndNot(nan, hn::And(visible, hn::Gt(rho, hn::Zero(df))));
    // facet::portable_log2's normal range in lanes: a subnormal rho's lane value is below 0 and an
    // infinite one's (128) above every level, as facet::portable_log2 gives them, so both clamp alike.
    const float top = static_cast<float>(texture.level_count() - 1);
    const VF lod = LevelLanes::clamp_to(hn::IfThenElseZero(logged, portable_log2(rho)), 0.0f, top);
    const VF l0 = hn::Floor(lod);
    const VF t = hn::Sub(lod, l0);
    const VI level = hn::ConvertTo(di, l0);
    ColourLanes out{hn::Zero(df), hn::Zero(df), hn::Zero(df), hn::Zero(df)};
    HWY_ALIGN std::int32_t levels[lanes];
    hn::Store(level, di, levels);
    for (std::uint64_t left = mask_bits(visible); left != 0;) {
        const int i = levels[std::countr_zero(left)];
        const MF these = hn::And(visible, hn::RebindMask(df, hn::Eq(level, hn::Set(di, i))));
        ColourLanes c = level_lanes(texture, i)(u, v, s);
        if (i + 1 < texture.level_count() && !hn::AllTrue(df, hn::Or(hn::Not(these), hn::Eq(t, hn::Zero(df)))))
            c = LevelLanes::mix(c, level_lanes(texture, i + 1)(u, v, s), t);  // t = 0: c exactly
        out = {hn::IfThenElse(these, hn::Div(c.r, k255), out.r), hn::IfThenElse(these, hn::Div(c.g, k255), out.g),
               hn::IfThenElse(these, hn::Div(c.b, k255), out.b), hn::IfThenElse(these, hn::Div(c.a, k255), out.a)};
        left &= ~mask_bits(these);
    }
    return out;
}

// ---- the shader ------------------------------------------------------------------------------------

// The lane-wide fragment() of PbrShader<NormalMap, false>.
template <class S>
struct PbrLanes {
    using Layout = typename S::Layout;
    static constexpr int N = S::k_varyings;
    static constexpr int D = S::k_derivative_count;  // the uv pair's derivatives, for the maps' mip levels
    static constexpr bool k_normal_map = Layout::has(shaders::Varying::tangent);
    const S& s;
    const EnvironmentLevels levels{s.pbr.environment};
    // Every channel's light the same for a grey base colour: the studio's grey environment, a tone
    // mapper of each channel alone (not ACES, whose matrix mixes them) and a grey emission.
    const bool grey_scene = grey_studio(s.pbr.environment) && s.pbr.tone_mapping != ToneMapping::aces &&
                            grey(s.pbr.emissive) && !s.pbr.emissive_map.texture;

    // A map sampled (shaders::detail::sample_map): bilinear and trilinear maps in lanes, the others by
    // the scalar sampler lane by lane.
    HWY_INLINE ColourLanes sample(const MapBinding& m, const LanesIn<N, D>& in) const {
        const DF df;
        constexpr int uv = Layout::at(shaders::Varying::uv);
        constexpr int lanes = static_cast<int>(hn::MaxLanes(DF()));
        HWY_ALIGN float u[lanes], v[lanes], ux[lanes], vx[lanes], uy[lanes], vy[lanes];
        HWY_ALIGN float out[4][lanes];
        hn::Store(in.v[uv], df, u), hn::Store(in.v[uv + 1], df, v);
        hn::Store(in.ddx[uv], df, ux), hn::Store(in.ddx[uv + 1], df, vx);
        hn::Store(in.ddy[uv], df, uy), hn::Store(in.ddy[uv + 1], df, vy);
        if (m.sampler.filter != Filter::nearest && !m.transformed)
            return sample_filtered(*m.texture, m.sampler, in.v[uv], in.v[uv + 1], in.ddx[uv], in.ddx[uv + 1], in.ddy[uv],
                                    in.ddy[uv + 1], in.visible);
        const std::uint64_t visible = mask_bits(in.visible);
        for (int l = 0; l < lanes; ++l) {
            const Vec4 t = (visible >> l) & 1 ? shaders::detail::sample_map(m, {u[l], v[l]}, {ux[l], vx[l]}, {uy[l], vy[l]}) : Vec4{};
            out[0][l] = t.x, out[1][l] = t.y, out[2][l] = t.z, out[3][l] = t.w;
        }
        return {hn::Load(df, out[0]), hn::Load(df, out[1]), hn::Load(df, out[2]), hn::Load(df, out[3])};
    }

    ColourLanes operator()(LanesIn<N, D>& in) const {
        const DF df;
        const PbrUniforms& p = s.pbr;
        // base_colour()
        ColourLanes base = colour_lanes<Layout>(in.v);
        if (p.base_colour.texture) {
            const ColourLanes t = sample(p.base_colour, in);
            base = {hn::Mul(base.r, srgb_to_linear(t.r)), hn::Mul(base.g, srgb_to_linear(t.g)),
                    hn::Mul(base.b, srgb_to_linear(t.b)), hn::Mul(base.a, t.a)};
        }
        const Vec3Lanes base_rgb{base.r, base.g, base.b};
        if (p.unlit) {
            const Vec3Lanes c = display(base_rgb, p);
            return {c.x, c.y, c.z, base.a};
        }
        VF metallic = hn::Set(df, p.metallic), roughness = hn::Set(df, p.roughness);
        if (p.metallic_roughness.texture) {
            const ColourLanes t = sample(p.metallic_roughness, in);
            roughness = hn::Mul(roughness, t.g);
            metallic = hn::Mul(metallic, t.b);
        }
        const Vec3Lanes n = normal(in);
        const Vec3Lanes position = vec3_lanes<Layout, shaders::Varying::position>(in.v);
        const Vec3Lanes v = normalize(sub(splat(s.u.eye), position), in.scalar);
        // A grey base colour in a grey scene: the three channels' operations are the same on the same
        // bits, so they are written on one vector (the compiler computes each once).
        const DU du;
        const auto r_bits = hn::BitCast(du, base.r);
        const MF grey_lanes = hn::RebindMask(df, hn::And(hn::Eq(r_bits, hn::BitCast(du, base.g)), hn::Eq(r_bits, hn::BitCast(du, base.b))));
        const Vec3Lanes out = grey_scene && hn::AllTrue(df, hn::Or(hn::Not(in.visible), grey_lanes))
                                  ? lit<true>(Vec3Lanes{base.r, base.r, base.r}, metallic, roughness, n, v, in)
                                  : lit<false>(base_rgb, metallic, roughness, n, v, in);
        return {out.x, out.y, out.z, base.a};
    }

    // The light of the surface and its display transform (fragment()'s rest); `Grey`: base's
    // channels are one vector and the scene is grey (grey_scene).
    template <bool Grey>
    HWY_INLINE Vec3Lanes lit(const Vec3Lanes& base, VF metallic, VF roughness, const Vec3Lanes& n, const Vec3Lanes& v,
                             const LanesIn<N, D>& in) const {
        const DF df;
        const PbrUniforms& p = s.pbr;
        Vec3Lanes c = image_based_light<Grey>(base, metallic, roughness, !p.metallic_roughness.texture, n, v, *p.environment);
        if (p.occlusion.texture) {
            const ColourLanes t = sample(p.occlusion, in);
            const VF ao = hn::Add(hn::Set(df, 1.0f), hn::Mul(hn::Set(df, p.occlusion_strength), hn::Sub(t.r, hn::Set(df, 1.0f))));
            c = mul(c, ao);
        }
        const VF grey_emissive = hn::Set(df, p.emissive.x);
        Vec3Lanes e = Grey ? Vec3Lanes{grey_emissive, grey_emissive, grey_emissive} : splat(p.emissive);
        if (!Grey && p.emissive_map.texture) {
            const ColourLanes t = sample(p.emissive_map, in);
            e = mul(e, Vec3Lanes{srgb_to_linear(t.r), srgb_to_linear(t.g), srgb_to_linear(t.b)});
        }
        return display(add(c, e), p);
    }

    // PbrShader::normal
    HWY_INLINE Vec3Lanes normal(LanesIn<N, D>& in) const {
        const DF df;
        Vec3Lanes n = normalize(vec3_lanes<Layout, shaders::Varying::normal>(in.v), in.scalar);
        if constexpr (k_normal_map) {
            const PbrUniforms& p = s.pbr;
            if (p.normal.texture) {
                constexpr int at = Layout::at(shaders::Varying::tangent);
                const Vec3Lanes tangent{in.v[at], in.v[at + 1], in.v[at + 2]};
                const VF side = in.v[at + 3];
                const Vec3Lanes t = normalize(sub(tangent, mul(n, dot(n, tangent))), in.scalar);
                const Vec3Lanes b = mul(Vec3Lanes{hn::Sub(hn::Mul(n.y, t.z), hn::Mul(n.z, t.y)),
                                                  hn::Sub(hn::Mul(n.z, t.x), hn::Mul(n.x, t.z)),
                                                  hn::Sub(hn::Mul(n.x, t.y), hn::Mul(n.y, t.x))},
                                        side);
                const ColourLanes m = sample(p.normal, in);
                const VF two = hn::Set(df, 2.0f), one = hn::Set(df, 1.0f), scale = hn::Set(df, p.normal_scale);
                const VF x = hn::Mul(hn::Sub(hn::Mul(two, m.r), one), scale);
                const VF y = hn::Mul(hn::Sub(hn::Mul(two, m.g), one), scale);
                const VF z = hn::Sub(hn::Mul(two, m.b), one);
                n = normalize(add(add(mul(t, x), mul(b, y)), mul(n, z)), in.scalar);
            }
        }
        return select(in.front_facing, n, negate(n));
    }

    // shaders::detail::image_based_light
    template <bool Grey>
    HWY_INLINE Vec3Lanes image_based_light(const Vec3Lanes& base, VF metallic, VF roughness, bool uniform_roughness,
                                           const Vec3Lanes& n, const Vec3Lanes& v, const Environment& env) const {
        const DF df;
        const VF one = hn::Set(df, 1.0f);
        const VF n_dot_v_raw = dot(n, v);
        const VF n_dot_v = clamp_zero_to(n_dot_v_raw, 1.0f);
        const Vec3Lanes r = sub(mul(n, hn::Mul(hn::Set(df, 2.0f), n_dot_v_raw)), v);
        VF a, b;
        split_sum(n_dot_v, roughness, uniform_roughness, a, b);
        const Vec3Lanes dielectric = splat3(0.04f);
        const Vec3Lanes f0 = add(dielectric, mul(sub(base, dielectric), metallic));
        const Vec3Lanes c_diff = mul(base, hn::Sub(one, metallic));
        const VF x = hn::Sub(one, n_dot_v), x5 = hn::Mul(hn::Mul(hn::Mul(hn::Mul(x, x), x), x), x);
        const VF smooth = hn::Sub(one, roughness);
        const Vec3Lanes fr = sub({greater_or_second(smooth, f0.x), greater_or_second(smooth, f0.y), greater_or_second(smooth, f0.z)}, f0);
        const Vec3Lanes k_s = add(f0, mul(fr, x5));
        const Vec3Lanes fss_ess = add(mul(k_s, a), Vec3Lanes{b, b, b});
        const VF ems = hn::Sub(one, hn::Add(a, b));
        const Vec3Lanes ones = splat3(1.0f);
        const Vec3Lanes f_avg = add(f0, mul(sub(ones, f0), hn::Set(df, 1 / 21.0f)));
        const Vec3Lanes fms_ems = {hn::Div(hn::Mul(hn::Mul(fss_ess.x, f_avg.x), ems), hn::Sub(one, hn::Mul(f_avg.x, ems))),
                                   hn::Div(hn::Mul(hn::Mul(fss_ess.y, f_avg.y), ems), hn::Sub(one, hn::Mul(f_avg.y, ems))),
                                   hn::Div(hn::Mul(hn::Mul(fss_ess.z, f_avg.z), ems), hn::Sub(one, hn::Mul(f_avg.z, ems)))};
        const Vec3Lanes k_d = mul(c_diff, add(sub(ones, fss_ess), fms_ems));
        const VF lod = hn::Mul(roughness, hn::Set(df, static_cast<float>(Environment::k_levels - 1)));
        const Vec3Lanes spec = mul(specular<Grey>(env, levels, r, lod, uniform_roughness), fss_ess);
        const Vec3Lanes diff = mul(add(fms_ems, k_d), diffuse<Grey>(env, n));
        return add(diff, spec);
    }
};

void ShadePbr(const shaders::Pbr& s, const VisibleTile& tile, TargetView target) {
    ShadeVisibleTile(s, PbrLanes<shaders::Pbr>{s}, tile, target);
}
void ShadePbrNormalMapped(const shaders::PbrNormalMapped& s, const VisibleTile& tile, TargetView target) {
    ShadeVisibleTile(s, PbrLanes<shaders::PbrNormalMapped>{s}, tile, target);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

FACET_DEFINE_VISIBLE_PASS(Pbr, ShadePbr)
FACET_DEFINE_VISIBLE_PASS(PbrNormalMapped, ShadePbrNormalMapped)

}  // namespace facet::detail
#endif
