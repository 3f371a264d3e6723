// facet simd: a float vector's mask as an integer of bits (lane i at bit i), for kernels that walk
// their lanes one by one (the passes' and the visible pass's rare lanes). A Highway "-inl.h" header:
// included once per target by each kernel file's foreach_target.h pass (the guard toggles with
// HWY_TARGET_TOGGLE).
#if defined(FACET_SIMD_MASK_BITS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef FACET_SIMD_MASK_BITS_INL_H_
#undef FACET_SIMD_MASK_BITS_INL_H_
#else
#define FACET_SIMD_MASK_BITS_INL_H_
#endif

#include <hwy/highway.h>

#include <cstdint>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The lanes of a mask of full float vectors as bits, lane i at bit i (at most 64 lanes).
HWY_INLINE std::uint64_t mask_bits(hn::Mask<hn::ScalableTag<float>> m) {
    std::uint8_t bytes[8] = {};
    hn::StoreMaskBits(hn::ScalableTag<float>(), m, bytes);
    std::uint64_t bits = 0;
    std::memcpy(&bits, bytes, sizeof(bits));
    return bits;
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif
