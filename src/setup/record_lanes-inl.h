// facet setup: what the SIMD set-up kernels share (setup_simd.cpp for triangles, raster/segment_simd.cpp
// for line segments): one record per double lane, its integers exact in the lanes, stored as the
// record's 32-bit words. A Highway "-inl.h" header: included once per target by each kernel file's
// foreach_target.h pass (the guard toggles with HWY_TARGET_TOGGLE).
#if defined(FACET_SETUP_RECORD_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef FACET_SETUP_RECORD_LANES_INL_H_
#undef FACET_SETUP_RECORD_LANES_INL_H_
#else
#define FACET_SETUP_RECORD_LANES_INL_H_
#endif

#include <hwy/highway.h>

#include <cstdint>

#include "setup/setup.hpp"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using DI = hn::Rebind<std::int32_t, D>;
using DU = hn::Rebind<std::uint32_t, D>;
using DF = hn::Rebind<float, D>;
using V = hn::Vec<D>;
using VU = hn::Vec<DU>;
using M = hn::Mask<D>;

HWY_INLINE std::uint32_t mask_bits(M m) {
    std::uint8_t bits[8] = {};
    hn::StoreMaskBits(D(), m, bits);
    return bits[0];  // at most 8 double lanes
}

// An integer-valued double lane as the 32-bit word a record stores (|v| < 2^31).
HWY_INLINE VU word_of_integer(V v) { return hn::BitCast(DU(), hn::DemoteTo(DI(), v)); }
HWY_INLINE VU word_of_float(V v) { return hn::BitCast(DU(), hn::DemoteTo(DF(), v)); }

// A mask of double lanes as one of 32-bit lanes (RebindMask needs lanes of one size).
HWY_INLINE hn::Mask<DU> word_mask(M m) {
    return hn::MaskFromVec(word_of_integer(hn::IfThenElseZero(m, hn::Set(D(), -1.0))));
}

// first_centre and last_centre of setup.hpp: floor(v / 256) is the arithmetic shift by 8.
HWY_INLINE V floor_div_256(V v) { return hn::Floor(hn::Mul(v, hn::Set(D(), 1.0 / k_subpixel_one))); }

// Words 4g..4g+3 of the records of lanes i0.. (see SetupLanes).
HWY_INLINE void store_unit(SetupLanes& out, int g, int i0, VU w0, VU w1, VU w2, VU w3) {
    hn::StoreInterleaved4(w0, w1, w2, w3, DU(), out.unit[g][i0].word);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif
