// facet tile pass: the tile stores (tile_store.hpp) and the deferred fills' streaming rows
// (deferred_fills.hpp) as SIMD kernels, compiled per ISA by Highway and dispatched at run time:
// finished tiles and clear values written to the target with streaming stores where their rows are
// whole aligned cache lines, copied by the specification (store_tile_row_reference) elsewhere.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tile/tile_store_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/cache_control.h>
#include <hwy/highway.h>

#include <algorithm>
#include <cstring>

#include "tile/deferred_fills.hpp"
#include "tile/stream_fill-inl.h"
#include "tile/tile_store.hpp"

HWY_BEFORE_NAMESPACE();
namespace facet::detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// store_tile_rows for this target: whole aligned cache lines streamed, the rest copied (the
// specification, store_tile_rows_reference, for rows that cannot be streamed). With `covered`, a
// pixel whose bit is clear gets `fill` instead.
void StoreTileRows(const std::uint32_t* HWY_RESTRICT rows, int rows_stride, const std::uint64_t* covered,
                   std::uint32_t fill, std::uint32_t* HWY_RESTRICT target, int width, int height, int target_stride,
                   bool fence) {
    const hn::ScalableTag<std::uint32_t> du;
    const int lanes = static_cast<int>(hn::Lanes(du));
    constexpr int k_line = 64 / sizeof(std::uint32_t);
    const auto fill_lanes = hn::Set(du, fill);
    bool streamed = false;
    for (int row = 0; row < height; ++row) {
        const std::uint32_t* from = rows + row * rows_stride;
        std::uint32_t* to = target + static_cast<std::size_t>(row) * static_cast<std::size_t>(target_stride);
        if (width % k_line != 0 || lanes > k_line || reinterpret_cast<std::uintptr_t>(to) % 64 != 0) {
            store_tile_row_reference(from, covered ? covered + row : nullptr, fill, to, width);
            continue;
        }
        for (int i = 0; i < width; i += lanes) {
            auto v = hn::LoadU(du, from + i);
            if (covered) {
                const std::uint64_t bits = covered[row] >> i;
                std::uint8_t bytes[8];
                std::memcpy(bytes, &bits, sizeof(bytes));
                v = hn::IfThenElse(hn::LoadMaskBits(du, bytes), v, fill_lanes);
            }
            hn::Stream(v, du, to + i);
        }
        streamed = true;
    }
    // Streaming stores are weakly ordered: make them visible before the tile is reported done.
    if (streamed && fence) hwy::FlushStream();
}

// The words may be floats (a depth buffer): Highway's stores may alias, the rest is copied bytes.
void FillWords(void* HWY_RESTRICT to, std::size_t count, std::uint32_t value) {
    const hn::ScalableTag<std::uint32_t> du;
    const std::size_t lanes = hn::Lanes(du);
    const auto word = hn::Set(du, value);
    auto* words = static_cast<std::uint32_t*>(to);
    std::size_t i = 0;
    for (; i + lanes <= count; i += lanes) hn::StoreU(word, du, words + i);
    for (; i < count; ++i) std::memcpy(words + i, &value, sizeof(value));
}

void FenceStreams() { hwy::FlushStream(); }

void FenceFills(DeferredFills& fills) {
    if (fills.streamed) hwy::FlushStream();
    fills.streamed = false;
}

void DrainFills(DeferredFills& fills) {
    while (fills.pending()) stream_fill_rows(fills, k_max_tile_size);
    FenceFills(fills);
}

}  // namespace facet::detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/isa.hpp"

namespace facet::detail {

HWY_EXPORT(StoreTileRows);
HWY_EXPORT(FillWords);
HWY_EXPORT(FenceStreams);
HWY_EXPORT(DrainFills);

void drain_fills(DeferredFills& fills) { HWY_DYNAMIC_DISPATCH(DrainFills)(fills); }

void fill_words(void* to, std::size_t count, std::uint32_t value) {
    if (!use_scalar_kernels()) return HWY_DYNAMIC_DISPATCH(FillWords)(to, count, value);
    for (std::size_t i = 0; i < count; ++i) std::memcpy(static_cast<char*>(to) + i * sizeof(value), &value, sizeof(value));
}

void fence_streams() {
    if (!use_scalar_kernels()) HWY_DYNAMIC_DISPATCH(FenceStreams)();
}

void store_tile_rows(const void* rows, int rows_stride, void* target_origin, PixelRect tile, int target_stride,
                     bool stream, const std::uint64_t* covered, std::uint32_t fill, bool fence) {
    const int width = tile.x1 - tile.x0, height = tile.y1 - tile.y0;
    const auto* from = static_cast<const std::uint32_t*>(rows);
    auto* to = static_cast<std::uint32_t*>(target_origin);
    if (stream && !use_scalar_kernels())
        return HWY_DYNAMIC_DISPATCH(StoreTileRows)(from, rows_stride, covered, fill, to, width, height, target_stride,
                                                   fence);
    for (int row = 0; row < height; ++row)
        store_tile_row_reference(from + row * rows_stride, covered ? covered + row : nullptr, fill,
                                 to + static_cast<std::size_t>(row) * static_cast<std::size_t>(target_stride), width);
}

namespace {
// Fills a row of pixels with one colour. std::fill of the 4-byte Rgba8 struct is not vectorized
// (2.5 times slower than Framebuffer::clear per pixel); a fill of 32-bit words is.
void fill_row(Rgba8* row, int width, Rgba8 colour) {
    std::uint32_t word;
    std::memcpy(&word, &colour, sizeof(word));
    std::uint32_t words[k_max_tile_size];
    std::fill_n(words, width, word);
    std::memcpy(row, words, static_cast<std::size_t>(width) * sizeof(word));
}
}  // namespace

void fill_rect(TargetView target, PixelRect r, Rgba8 colour, float depth, bool stream) {
    alignas(64) Rgba8 colour_row[k_max_tile_size];
    alignas(64) float depth_row[k_max_tile_size];
    const int width = r.x1 - r.x0;
    fill_row(colour_row, width, colour);
    std::fill_n(depth_row, width, depth);
    store_tile_rows(colour_row, 0, target.colour + target.at(r.x0, r.y0), r, target.stride, stream);
    store_tile_rows(depth_row, 0, target.depth + target.at(r.x0, r.y0), r, target.stride, stream);
}

}  // namespace facet::detail
#endif
