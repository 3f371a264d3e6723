// facet raster: the depth pass of the visible-only drawing order (detail/shade.hpp) as a SIMD kernel,
// compiled per ISA by Highway and dispatched at run time. Lanes compute each pixel's depth with the
// same operations in the same order as depth_at (no FMA: the project builds with -ffp-contract=off
// and Highway's Mul and Add round separately), so every ISA writes the bytes of the scalar
// specification, resolve_depth_reference in detail/shade.hpp. Columns past the last whole group of lanes
// (tiles narrower than a vector, the target's right edge) go through depth_at one by one.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/depth_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <cstring>

#include "facet/detail/shade.hpp"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class DF, class M>
M depth_test(DF, DepthTest test, hn::Vec<DF> z, hn::Vec<DF> stored, M covered) {
    switch (test) {
        case DepthTest::less: return hn::And(covered, hn::Lt(z, stored));
        case DepthTest::lequal: return hn::And(covered, hn::Le(z, stored));
        case DepthTest::equal: return hn::And(covered, hn::Eq(z, stored));
        case DepthTest::greater: return hn::And(covered, hn::Gt(z, stored));
        case DepthTest::always: return covered;
        case DepthTest::never: break;
    }
    return hn::And(covered, hn::Lt(z, hn::Zero(DF())));  // never: z >= 0 after clamping, so no lane
}

void ResolveDepth(const DepthJob& job) {
    const hn::ScalableTag<float> df;
    const hn::RebindToUnsigned<decltype(df)> du;
    const int lanes = static_cast<int>(hn::Lanes(df));
    const TriangleSetup& t = *job.setup;
    const TileCoverage& cov = *job.coverage;
    const PixelRect tile = job.tile;
    const auto zero = hn::Zero(df), one = hn::Set(df, 1.0f);
    const auto z0 = hn::Set(df, t.z0), dzdx = hn::Set(df, t.dzdx), x0 = hn::Set(df, t.x0), half = hn::Set(df, 0.5f);
    const auto id = hn::Set(du, job.id);
    const std::uint64_t lane_bits = lanes >= 64 ? ~0ull : (1ull << lanes) - 1;
    const int simd_end = tile.x0 + (tile.x1 - tile.x0) / lanes * lanes;  // whole groups inside the tile

    for (int row = cov.first_row; row <= cov.last_row; ++row) {
        const std::uint64_t mask = cov.rows[row];
        if (!mask) continue;
        const int y = tile.y0 + row;
        const float dy = (static_cast<float>(y) + 0.5f) - t.y0;
        const auto z_dy = hn::Set(df, t.dzdy * dy);
        float* depth_row = job.target.depth + static_cast<std::size_t>(y) * job.target.stride;
        std::uint32_t* owner_row = job.owner + row * k_max_tile_size;
        for (int x = tile.x0; x < simd_end; x += lanes) {
            const int i = x - tile.x0;
            const std::uint64_t bits = (mask >> i) & lane_bits;
            if (!bits) continue;
            std::uint8_t bytes[8];
            std::memcpy(bytes, &bits, sizeof(bytes));
            const auto covered = hn::LoadMaskBits(df, bytes);
            // z = (z0 + dzdx dx) + dzdy dy, clamped to [0, 1] (NaN stays NaN), as depth_at.
            const auto dx = hn::Sub(hn::Add(hn::Iota(df, static_cast<float>(x)), half), x0);
            auto z = hn::Add(hn::Add(z0, hn::Mul(dzdx, dx)), z_dy);
            z = hn::IfThenElse(hn::Lt(z, zero), zero, hn::IfThenElse(hn::Gt(z, one), one, z));
            const auto stored = hn::LoadU(df, depth_row + x);
            const auto pass = depth_test(df, job.test, z, stored, covered);
            if (job.write) hn::StoreU(hn::IfThenElse(pass, z, stored), df, depth_row + x);
            const auto owners = hn::LoadU(du, owner_row + i);
            hn::StoreU(hn::IfThenElse(hn::RebindMask(du, pass), id, owners), du, owner_row + i);
        }
        for (int x = simd_end; x < tile.x1; ++x) {
            const int i = x - tile.x0;
            if (!((mask >> i) & 1)) continue;
            const float z = depth_at(t, x, y);
            if (!depth_passes(job.test, z, depth_row[x])) continue;
            if (job.write) depth_row[x] = z;
            owner_row[i] = job.id;
        }
    }
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {
namespace {

void resolve_depth_scalar(const DepthJob& job) {
    auto with_write = [&]<DepthTest D>() {
        job.write ? resolve_depth_reference<D, true>(job) : resolve_depth_reference<D, false>(job);
    };
    with_depth_test(job.test, with_write);
}

}  // namespace

HWY_EXPORT(ResolveDepth);

void resolve_depth(const DepthJob& job) {
    if (use_scalar_kernels()) return resolve_depth_scalar(job);
    HWY_DYNAMIC_DISPATCH(ResolveDepth)(job);
}
}  // namespace facet::detail
#endif
