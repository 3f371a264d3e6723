// facet tile pass: a row of a tile's render passes (write_pass_row, passes.hpp) as a SIMD kernel,
// compiled per ISA by Highway and dispatched at run time. In: the row's owners and covered bits,
// each listed triangle's pass record. Out: the row's passes, a vector of pixels at a time. Every
// lane performs write_pass_pixel's operations in the same order with the same rounding (no FMA,
// correctly rounded sqrt and division), so the bytes are the specification's; what has no exact
// vector form goes through it pixel by pixel: the rare normals of normalize_rare and the columns
// past the last whole vector. Does not decide visibility; streams the row to the targets only
// when asked to (whole aligned cache lines), else leaves it in the row buffer.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tile/passes_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/cache_control.h>
#include <hwy/highway.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>

#include "tile/passes.hpp"
#include "simd/mask_bits-inl.h"
#include "simd/masked_compare-inl.h"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using DU = hn::RebindToUnsigned<DF>;
using VF = hn::Vec<DF>;
using VU = hn::Vec<DU>;
using MF = hn::Mask<DF>;
using MU = hn::Mask<DU>;

// One vector of pixels of every pass (those the targets do not want are left unset).
struct PassLanes {
    VF depth, range, nx, ny, nz, u, v;
    VU primitive;
};

// write_pass_pixel for the lanes whose pixel centres are (px, py), each triangle value read by
// setup(&TriangleSetup::member) or field(j) (pass record offset j; field_u for the primitive's bits).
// Lanes whose normal needs normalize_rare are added to `scalar`.
template <class Setup, class Field, class FieldU>
HWY_INLINE PassLanes pass_lanes(const PassDraw& d, const Setup& setup, const Field& field, const FieldU& field_u,
                                VF px, VF py, MF& scalar) {
    const DF df;
    const DrawPasses& p = *d.passes;
    const PassTargets& t = p.targets;
    const PassLayout& l = d.layout;
    const int n = l.count;
    PassLanes o;
    const VF dx = hn::Sub(px, setup(&TriangleSetup::x0)), dy = hn::Sub(py, setup(&TriangleSetup::y0));
    const VF q = hn::Add(hn::Add(setup(&TriangleSetup::q0), hn::Mul(setup(&TriangleSetup::dqdx), dx)), hn::Mul(setup(&TriangleSetup::dqdy), dy));
    const VF w = hn::Div(hn::Set(df, 1.0f), q);
    if (t.depth || t.range) {
        if (p.depth_scale == 0) {
            o.depth = w;
        } else {  // depth_at: the window depth clamped to [0, 1] (NaN kept)
            VF z = hn::Add(hn::Add(setup(&TriangleSetup::z0), hn::Mul(setup(&TriangleSetup::dzdx), dx)), hn::Mul(setup(&TriangleSetup::dzdy), dy));
            const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f);
            z = hn::IfThenElse(hn::Lt(z, zero), zero, hn::IfThenElse(hn::Gt(z, one), one, z));
            o.depth = hn::Add(hn::Set(df, p.depth_offset), hn::Mul(hn::Set(df, p.depth_scale), z));
        }
        if (t.range) {
            auto ray = [&](int k) {
                return hn::Add(hn::Add(hn::Set(df, p.ray[k]), hn::Mul(hn::Set(df, p.ray[k + 1]), px)),
                               hn::Mul(hn::Set(df, p.ray[k + 2]), py));
            };
            const VF a = ray(0), b = ray(3);
            o.range = hn::Mul(o.depth, hn::Sqrt(hn::Add(hn::Add(hn::Set(df, 1.0f), hn::Mul(a, a)), hn::Mul(b, b))));
        }
    }
    VF b1 = hn::Zero(df), b2 = hn::Zero(df);
    if (n > 0) {
        const VF zero = hn::Zero(df);
        b1 = hn::Mul(hn::Add(hn::Add(zero, hn::Mul(setup(&TriangleSetup::dl1dx), dx)), hn::Mul(setup(&TriangleSetup::dl1dy), dy)), w);
        b2 = hn::Mul(hn::Add(hn::Add(zero, hn::Mul(setup(&TriangleSetup::dl2dx), dx)), hn::Mul(setup(&TriangleSetup::dl2dy), dy)), w);
    }
    auto varying = [&](int k) {
        return hn::Add(hn::Add(field(k_pass_head + k), hn::Mul(b1, field(k_pass_head + n + k))),
                       hn::Mul(b2, field(k_pass_head + 2 * n + k)));
    };
    if (t.normal) {
        VF x, y, z;
        if (l.normal_at >= 0) {
            x = varying(l.normal_at), y = varying(l.normal_at + 1), z = varying(l.normal_at + 2);
            // facet::normalize's common case, a / length(a); the others to the specification.
            const VF length = hn::Sqrt(hn::Add(hn::Add(hn::Add(hn::Zero(df), hn::Mul(x, x)), hn::Mul(y, y)), hn::Mul(z, z)));
            const MF ok = and_compare<Compare::gt>(
                df, hn::Lt(length, hn::Set(df, std::numeric_limits<float>::infinity())), length, hn::Zero(df));
            scalar = hn::Or(scalar, hn::Not(ok));
            x = hn::Div(x, length), y = hn::Div(y, length), z = hn::Div(z, length);
        } else {
            x = field(ph_face_x), y = field(ph_face_y), z = field(ph_face_z);
        }
        if (l.rotate_normals) {  // Mat3 * Vec3: col[0] * x + col[1] * y + col[2] * z
            const Mat3& m = p.normal_space;
            auto row = [&](int c) {
                return hn::Add(hn::Add(hn::Mul(hn::Set(df, m.col[0][c]), x), hn::Mul(hn::Set(df, m.col[1][c]), y)),
                               hn::Mul(hn::Set(df, m.col[2][c]), z));
            };
            const VF rx = row(0), ry = row(1), rz = row(2);
            x = rx, y = ry, z = rz;
        }
        o.nx = x, o.ny = y, o.nz = z;
    }
    if (t.uv) {
        if (l.uv_at >= 0) o.u = varying(l.uv_at), o.v = varying(l.uv_at + 1);
        else o.u = o.v = hn::Zero(df);
    }
    if (t.primitive) o.primitive = hn::Add(field_u(ph_primitive), hn::Set(DU(), 1u));
    return o;
}

// A whole vector of 4-byte values to `to` (its lanes' place in a row); streamed with kStream (`to`
// then starts a cache line or a vector's part of one).
template <bool kStream, class D>
HWY_INLINE void put(D d, hn::Vec<D> v, hn::TFromD<D>* to) {
    if constexpr (kStream) hn::Stream(v, d, to);
    else hn::StoreU(v, d, to);
}

// Interleaved Vec3 or Vec2 lanes to `to`: streamed with kStream, through a vector's worth of pixels
// on the stack (Highway's interleaving stores do not stream).
template <bool kStream>
HWY_INLINE void put3(VF x, VF y, VF z, float* to) {
    const DF df;
    if constexpr (kStream) {
        constexpr std::size_t lanes = hn::MaxLanes(DF());
        HWY_ALIGN float v[3 * lanes];
        hn::StoreInterleaved3(x, y, z, df, v);
        for (std::size_t k = 0; k < 3; ++k) hn::Stream(hn::Load(df, v + k * lanes), df, to + k * lanes);
    } else {
        hn::StoreInterleaved3(x, y, z, df, to);
    }
}
template <bool kStream>
HWY_INLINE void put2(VF u, VF v, float* to) {
    const DF df;
    if constexpr (kStream) {
        constexpr std::size_t lanes = hn::MaxLanes(DF());
        HWY_ALIGN float uv[2 * lanes];
        hn::StoreInterleaved2(u, v, df, uv);
        for (std::size_t k = 0; k < 2; ++k) hn::Stream(hn::Load(df, uv + k * lanes), df, to + k * lanes);
    } else {
        hn::StoreInterleaved2(u, v, df, to);
    }
}

// The lanes of `o` into [i, i + lanes) of `out`: with `whole` every lane (the background where not
// visible), else the visible lanes only; with kStream (and `whole`), streamed to `out`, the targets'
// row of whole aligned cache lines.
template <bool kStream = false>
HWY_INLINE void store_pass_lanes(const PassDraw& d, const PassLanes& o, MF visible, bool whole, const PassOut& out,
                                 int i) {
    const DF df;
    const DU du;
    const MU visible_u = hn::RebindMask(du, visible);
    const DrawPasses& p = *d.passes;
    const VF inf = hn::Set(df, std::numeric_limits<float>::infinity());
    constexpr std::size_t lanes = hn::MaxLanes(DF());
    auto store = [&](VF v, VF background, float* to) {
        if (whole) put<kStream>(df, hn::IfThenElse(visible, v, background), to + i);
        else hn::BlendedStore(v, visible, df, to + i);
    };
    auto store_u = [&](VU v, std::uint32_t* to) {
        if (whole) put<kStream>(du, hn::IfThenElseZero(visible_u, v), to + i);
        else hn::BlendedStore(v, visible_u, du, to + i);
    };
    // Vec3 and Vec2 rows as floats (Highway's stores may alias): interleaved whole when every lane is
    // written, else through a vector's worth of pixels of their own.
    const bool all = whole || hn::AllTrue(df, visible);
    const std::uint64_t bits = all ? 0 : mask_bits(visible);
    if (out.alpha) store(hn::Set(df, 1.0f), hn::Zero(df), out.alpha);
    if (out.depth) store(o.depth, inf, out.depth);
    if (out.range) store(o.range, inf, out.range);
    if (out.normal) {
        const VF x = hn::IfThenElseZero(visible, o.nx), y = hn::IfThenElseZero(visible, o.ny),
                 z = hn::IfThenElseZero(visible, o.nz);
        if (all) {
            put3<kStream>(x, y, z, reinterpret_cast<float*>(out.normal + i));
        } else {
            HWY_ALIGN Vec3 normals[lanes];
            hn::StoreInterleaved3(x, y, z, df, reinterpret_cast<float*>(normals));
            for (std::uint64_t b = bits; b; b &= b - 1) out.normal[i + std::countr_zero(b)] = normals[std::countr_zero(b)];
        }
    }
    if (out.instance) store_u(hn::Set(du, p.instance), out.instance);
    if (out.material) store_u(hn::Set(du, p.material), out.material);
    if (out.primitive) store_u(o.primitive, out.primitive);
    if (out.uv) {
        const VF u = hn::IfThenElseZero(visible, o.u), v = hn::IfThenElseZero(visible, o.v);
        if (all) {
            put2<kStream>(u, v, reinterpret_cast<float*>(out.uv + i));
        } else {
            HWY_ALIGN Vec2 uvs[lanes];
            hn::StoreInterleaved2(u, v, df, reinterpret_cast<float*>(uvs));
            for (std::uint64_t b = bits; b; b &= b - 1) out.uv[i + std::countr_zero(b)] = uvs[std::countr_zero(b)];
        }
    }
}

// The background into [i, i + lanes) of `out` (streamed with kStream, as store_pass_lanes).
template <bool kStream = false>
HWY_INLINE void store_pass_background(const PassOut& out, int i) {
    const DF df;
    const DU du;
    const VF zero = hn::Zero(df), inf = hn::Set(df, std::numeric_limits<float>::infinity());
    if (out.alpha) put<kStream>(df, zero, out.alpha + i);
    if (out.depth) put<kStream>(df, inf, out.depth + i);
    if (out.range) put<kStream>(df, inf, out.range + i);
    if (out.normal) put3<kStream>(zero, zero, zero, reinterpret_cast<float*>(out.normal + i));
    if (out.instance) put<kStream>(du, hn::Zero(du), out.instance + i);
    if (out.material) put<kStream>(du, hn::Zero(du), out.material + i);
    if (out.primitive) put<kStream>(du, hn::Zero(du), out.primitive + i);
    if (out.uv) put2<kStream>(zero, zero, reinterpret_cast<float*>(out.uv + i));
}

// Whether every pass of `to` (a row of the targets) starts on a cache line and is whole cache lines
// for `width` pixels.
bool whole_lines(const PassOut& to, int width) {
    if (width % 16 != 0) return false;
    auto aligned = [](const void* p) { return reinterpret_cast<std::uintptr_t>(p) % 64 == 0; };
    return aligned(to.alpha) && aligned(to.depth) && aligned(to.range) && aligned(to.normal) && aligned(to.instance) &&
           aligned(to.material) && aligned(to.primitive) && aligned(to.uv);
}

// [i, i + lanes) of each pass of `from` (a row buffer, whole) streamed to `to` (whole aligned lines).
HWY_INLINE void stream_pass_lanes(const PassOut& from, const PassOut& to, int i) {
    const DF df;
    constexpr int lanes = static_cast<int>(hn::MaxLanes(DF()));
    for_each_pass(from, to, [&](const void* src, void* dst, int components) {
        if (!dst) return;
        const float* s = static_cast<const float*>(src) + i * components;
        float* t = static_cast<float*>(dst) + i * components;
        for (int k = 0; k < components; ++k) hn::Stream(hn::Load(df, s + k * lanes), df, t + k * lanes);
    });
}

// GCC 12 cannot see that the runs found from the leaders' bits fill run_record[0, runs) before the
// blends read it, and warns; the entries read are exactly those written.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
bool WritePassRow(const VisibleTile& tile, const float* records, int record_stride, const PassDraw& d, int r,
                  std::uint64_t pixels, const PassOut& out, bool whole, const PassOut* stream) {
    const DF df;
    const DU du;
    constexpr int lanes = static_cast<int>(hn::MaxLanes(DF()));
    constexpr std::uint64_t lane_bits = lanes >= 64 ? ~0ull : (1ull << lanes) - 1;
    const int width = tile.rect.x1 - tile.rect.x0, simd_width = width / lanes * lanes;
    // Straight to the targets: each vector streamed from the registers, or, when the specification
    // must mend some of its lanes first, through `out` at its place (in the caches).
    const bool direct = whole && stream && simd_width == width && whole_lines(*stream, width);
    const std::uint32_t* owner_row = tile.owner + r * VisibleTile::k_row;
    const VF py = hn::Set(df, static_cast<float>(tile.rect.y0 + r) + 0.5f);
    // Lane l's left neighbour (itself for lane 0, which has none).
    using LaneIndices = decltype(hn::SetTableIndices(du, static_cast<const std::int32_t*>(nullptr)));
    HWY_ALIGN std::int32_t left_index[lanes];
    for (int l = 0; l < lanes; ++l) left_index[l] = l > 0 ? l - 1 : 0;
    const LaneIndices left = hn::SetTableIndices(du, left_index);
    const MU not_first = hn::RebindMask(du, hn::Not(hn::FirstN(df, 1)));
    std::uint64_t redo = 0;
    for (int i = 0; i < simd_width; i += lanes) {
        const std::uint64_t bits = (pixels >> i) & lane_bits;
        if (!bits) {
            if (direct) store_pass_background<true>(*stream, i);
            else if (whole) store_pass_background(out, i);
            continue;
        }
        std::uint8_t bytes[8];
        std::memcpy(bytes, &bits, sizeof(bytes));
        const MF visible = hn::LoadMaskBits(df, bytes);
        const VU owners = hn::LoadU(du, owner_row + i);
        // The triangles owning the visible lanes, each lane's record values assembled from one
        // broadcast per triangle (as the shading kernels do): a run starts at each visible lane whose
        // left neighbour has another owner; a triangle split by another leads twice, harmlessly.
        HWY_ALIGN std::uint32_t owner_of[lanes];
        hn::Store(owners, du, owner_of);
        MF run_mask[lanes];
        const float* run_record[lanes];
        const TriangleSetup* run_setup[lanes];
        const std::uint32_t first_owner = owner_of[std::countr_zero(bits)];
        run_record[0] = records + static_cast<std::size_t>(first_owner) * static_cast<std::size_t>(record_stride);
        run_setup[0] = tile.triangles[first_owner];
        int runs = 1;
        const MF first_run = hn::RebindMask(df, hn::Eq(owners, hn::Set(du, first_owner)));
        if (!hn::AllFalse(df, hn::AndNot(first_run, visible))) {
            const MU repeats = and_compare<Compare::eq>(du, not_first, owners, hn::TableLookupLanes(owners, left));
            std::uint64_t leaders = mask_bits(hn::AndNot(hn::RebindMask(df, repeats), visible));
            for (leaders &= leaders - 1; leaders != 0; leaders &= leaders - 1, ++runs) {
                const std::uint32_t owner = owner_of[std::countr_zero(leaders)];
                run_mask[runs] = hn::RebindMask(df, hn::Eq(owners, hn::Set(du, owner)));
                run_record[runs] = records + static_cast<std::size_t>(owner) * static_cast<std::size_t>(record_stride);
                run_setup[runs] = tile.triangles[owner];
            }
        }
        const VF px = hn::Add(hn::Iota(df, static_cast<float>(tile.rect.x0 + i)), hn::Set(df, 0.5f));
        MF scalar = hn::FirstN(df, 0);
        PassLanes o;
        if (runs == 1) {  // one triangle: plain broadcasts
            const float* record = run_record[0];
            const TriangleSetup& t = *run_setup[0];
            auto setup = [&](float TriangleSetup::*m) { return hn::Set(df, t.*m); };
            auto field = [&](int j) { return hn::Set(df, record[j]); };
            auto field_u = [&](int j) {
                std::uint32_t u;
                std::memcpy(&u, record + j, sizeof(u));
                return hn::Set(du, u);
            };
            o = pass_lanes(d, setup, field, field_u, px, py, scalar);
        } else {
            auto setup = [&](float TriangleSetup::*m) {
                VF v = hn::Set(df, run_setup[0]->*m);
                for (int k = 1; k < runs; ++k) v = hn::IfThenElse(run_mask[k], hn::Set(df, run_setup[k]->*m), v);
                return v;
            };
            auto field = [&](int j) {
                VF v = hn::Set(df, run_record[0][j]);
                for (int k = 1; k < runs; ++k) v = hn::IfThenElse(run_mask[k], hn::Set(df, run_record[k][j]), v);
                return v;
            };
            auto field_u = [&](int j) {
                auto at = [&](int k) {
                    std::uint32_t u;
                    std::memcpy(&u, run_record[k] + j, sizeof(u));
                    return hn::Set(du, u);
                };
                VU v = at(0);
                for (int k = 1; k < runs; ++k) v = hn::IfThenElse(hn::RebindMask(du, run_mask[k]), at(k), v);
                return v;
            };
            o = pass_lanes(d, setup, field, field_u, px, py, scalar);
        }
        const std::uint64_t rare = mask_bits(hn::And(scalar, visible)) & bits;
        if (direct && !rare) {
            store_pass_lanes<true>(d, o, visible, true, *stream, i);
            continue;
        }
        store_pass_lanes(d, o, visible, whole, out, i);
        if (direct) {
            for (std::uint64_t b = rare; b; b &= b - 1)
                write_pass_pixel(tile, records, record_stride, d, r, i + std::countr_zero(b), out);
            stream_pass_lanes(out, *stream, i);
        } else {
            redo |= rare << i;
        }
    }
    if (direct) return true;
    // The columns past the last whole vector, and the lanes the vectors could not do.
    if (whole) fill_pass_background(out, simd_width, width);
    redo |= simd_width >= 64 ? 0 : pixels & (~0ull << simd_width);
    for (; redo; redo &= redo - 1) write_pass_pixel(tile, records, record_stride, d, r, std::countr_zero(redo), out);
    return false;
}
#pragma GCC diagnostic pop

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace facet::detail {

HWY_EXPORT(WritePassRow);

bool write_pass_row(const VisibleTile& tile, const float* records, int record_stride, const PassDraw& d, int r,
                    std::uint64_t pixels, const PassOut& out, bool whole, const PassOut* stream) {
    return HWY_DYNAMIC_DISPATCH(WritePassRow)(tile, records, record_stride, d, r, pixels, out, whole, stream);
}

}  // namespace facet::detail
#endif
