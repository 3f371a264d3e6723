// facet tile pass: writing rows of a worker's deferred fills (DeferredFills, deferred_fills.hpp) with
// streaming stores, for the kernels that do it between their own work (the shading pass, through
// VisibleTile::idle) and for drain_fills (tile_store_simd.cpp). A Highway "-inl.h" header: included once per target by each kernel
// file's foreach_target.h pass (the guard toggles with HWY_TARGET_TOGGLE).
#if defined(FACET_TILE_STREAM_FILL_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef FACET_TILE_STREAM_FILL_INL_H_
#undef FACET_TILE_STREAM_FILL_INL_H_
#else
#define FACET_TILE_STREAM_FILL_INL_H_
#endif

#include <hwy/highway.h>

#include "tile/deferred_fills.hpp"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// One row of deferred fills (DeferredFills::take) in whole vectors streamed past the caches: the
// widest stores the CPU has, since narrower ones cost more per line (16-byte ones measured twice
// the cost of 64-byte ones in a frame).
HWY_INLINE void stream_fill_row(const DeferredFills::Row& row) {
    const hn::ScalableTag<std::uint32_t> du;
    const auto word = hn::Set(du, row.word);
    for (int i = 0; i < row.width; i += static_cast<int>(hn::Lanes(du))) hn::Stream(word, du, row.to + i);
}

// Up to `rows` rows of the queue.
HWY_INLINE void stream_fill_rows(DeferredFills& fills, int rows) {
    DeferredFills::Row row;
    for (int k = 0; k < rows && fills.take(row); ++k) stream_fill_row(row);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // FACET_TILE_STREAM_FILL_INL_H_ toggle
