// facet simd: a compare ANDed with a mask, `m AND (a <op> b)`, for the kernels' per-row and per-block
// lane masks. On AVX-512 hn::And(m, hn::Lt(a, b)) compiles to a compare and a kandw; a masked compare
// (vcmpps / vpcmpd with a {k} write mask) does both in one instruction and takes the kandw off the
// chain. Other targets use Highway's And of the compare: the same lanes on every target. A Highway
// "-inl.h" header: included once per target by each kernel file's foreach_target.h pass (the guard
// toggles with HWY_TARGET_TOGGLE).
#if defined(FACET_SIMD_MASKED_COMPARE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef FACET_SIMD_MASKED_COMPARE_INL_H_
#undef FACET_SIMD_MASKED_COMPARE_INL_H_
#else
#define FACET_SIMD_MASKED_COMPARE_INL_H_
#endif

#include <hwy/highway.h>

#include <cstdint>
#include <type_traits>

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The comparisons, with the predicates Highway's Lt, Le, Eq, Ne, Gt and Ge use on AVX-512 (ordered:
// false where a float lane is NaN).
enum class Compare { lt, le, eq, ne, gt, ge };

// and_compare on targets without masked compares. Integer lanes have no Le / Ge in every Highway:
// their complements under the mask instead (integers have no NaN).
template <Compare C, class D, class M>
HWY_INLINE M and_compare_portable(D, M m, hn::Vec<D> a, hn::Vec<D> b) {
    constexpr bool is_float = std::is_floating_point_v<hn::TFromD<D>>;
    if constexpr (C == Compare::lt) return hn::And(m, hn::Lt(a, b));
    else if constexpr (C == Compare::eq) return hn::And(m, hn::Eq(a, b));
    else if constexpr (C == Compare::ne) return hn::And(m, hn::Ne(a, b));
    else if constexpr (C == Compare::gt) return hn::And(m, hn::Gt(a, b));
    else if constexpr (C == Compare::le) {
        if constexpr (is_float) return hn::And(m, hn::Le(a, b));
        else return hn::AndNot(hn::Gt(a, b), m);
    } else {
        if constexpr (is_float) return hn::And(m, hn::Ge(a, b));
        else return hn::AndNot(hn::Lt(a, b), m);
    }
}

// The lanes of m where `a <op> b` (float, or signed / unsigned 32-bit integer lanes).
template <Compare C, class D, class M>
HWY_INLINE M and_compare(D d, M m, hn::Vec<D> a, hn::Vec<D> b) {
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
    using T = hn::TFromD<D>;
    constexpr int bytes = sizeof(a.raw);
    if constexpr (std::is_same_v<T, float> && (bytes == 64 || bytes == 32 || bytes == 16)) {
        constexpr int p = C == Compare::lt   ? _CMP_LT_OQ
                          : C == Compare::le ? _CMP_LE_OQ
                          : C == Compare::eq ? _CMP_EQ_OQ
                          : C == Compare::ne ? _CMP_NEQ_OQ
                          : C == Compare::gt ? _CMP_GT_OQ
                                             : _CMP_GE_OQ;
        if constexpr (bytes == 64) return M{_mm512_mask_cmp_ps_mask(m.raw, a.raw, b.raw, p)};
        else if constexpr (bytes == 32) return M{_mm256_mask_cmp_ps_mask(m.raw, a.raw, b.raw, p)};
        else return M{_mm_mask_cmp_ps_mask(m.raw, a.raw, b.raw, p)};
    } else if constexpr (std::is_integral_v<T> && sizeof(T) == 4 && (bytes == 64 || bytes == 32 || bytes == 16)) {
        // _MM_CMPINT_GT / _GE are _NLE / _NLT: the integer compares have no NaN.
        constexpr int p = C == Compare::lt   ? _MM_CMPINT_LT
                          : C == Compare::le ? _MM_CMPINT_LE
                          : C == Compare::eq ? _MM_CMPINT_EQ
                          : C == Compare::ne ? _MM_CMPINT_NE
                          : C == Compare::gt ? _MM_CMPINT_NLE
                                             : _MM_CMPINT_NLT;
        if constexpr (std::is_signed_v<T>) {
            if constexpr (bytes == 64) return M{_mm512_mask_cmp_epi32_mask(m.raw, a.raw, b.raw, p)};
            else if constexpr (bytes == 32) return M{_mm256_mask_cmp_epi32_mask(m.raw, a.raw, b.raw, p)};
            else return M{_mm_mask_cmp_epi32_mask(m.raw, a.raw, b.raw, p)};
        } else {
            if constexpr (bytes == 64) return M{_mm512_mask_cmp_epu32_mask(m.raw, a.raw, b.raw, p)};
            else if constexpr (bytes == 32) return M{_mm256_mask_cmp_epu32_mask(m.raw, a.raw, b.raw, p)};
            else return M{_mm_mask_cmp_epu32_mask(m.raw, a.raw, b.raw, p)};
        }
    } else {
        return and_compare_portable<C>(d, m, a, b);
    }
#else
    return and_compare_portable<C>(d, m, a, b);
#endif
}

// Whether no lane is set in both a and b: on AVX-512 one ktest, not a kand and a kortest.
template <class D, class M>
HWY_INLINE bool none_in_both(D d, M a, M b) {
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
    if constexpr (std::is_same_v<decltype(a.raw), __mmask16>) return _ktestz_mask16_u8(a.raw, b.raw) != 0;
    else if constexpr (std::is_same_v<decltype(a.raw), __mmask8>) return _ktestz_mask8_u8(a.raw, b.raw) != 0;
    else return hn::AllFalse(d, hn::And(a, b));
#else
    return hn::AllFalse(d, hn::And(a, b));
#endif
}

// The lanes of m where a < b (32-bit integers, as the depth pass's rows).
template <class D, class M>
HWY_INLINE M and_less(D d, M m, hn::Vec<D> a, hn::Vec<D> b) {
    return and_compare<Compare::lt>(d, m, a, b);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif
