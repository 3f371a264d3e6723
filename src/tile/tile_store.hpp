// facet tile pass: writing finished tiles to the target. In: rows of a tile's own buffer (colour or
// depth, 4-byte values), or one value to fill a rectangle with. Out: the target's pixels of that
// tile, streamed past the caches where the rows are whole aligned cache lines and nothing of this
// draw reads them again, copied otherwise. Does not decide which tiles are cleared (tile_pass.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "facet/detail/frame.hpp"

namespace facet::detail {

// Writes the rows of `tile` in the target (4-byte values: colour or depth) from rows `rows_stride`
// values apart starting at `rows` (0: the same row every time, for a fill), to `target_origin`, rows
// `target_stride` values apart. With `stream`, rows that are whole cache lines at aligned addresses
// are written with streaming stores (SIMD, tile_store_simd.cpp): the target's lines are not read
// first, nor kept in the caches; for tiles the draw cleared, which nothing reads again in this draw.
// The others are copied. With `covered` (one 64-bit row mask per row, bit i for pixel tile.x0 + i),
// a pixel whose bit is clear is written `fill` instead of its value in `rows`. Streaming stores are
// fenced before it returns, unless `fence` is false: then the caller calls fence_streams() after its
// last streaming store, before another thread may read what it wrote (the tile pass: once per worker
// at the end of a batch).
void store_tile_rows(const void* rows, int rows_stride, void* target_origin, PixelRect tile, int target_stride,
                     bool stream, const std::uint64_t* covered = nullptr, std::uint32_t fill = 0, bool fence = true);
// Makes this thread's streaming stores visible to the others (store_tile_rows without its fence).
void fence_streams();
template <class T>
void store_tile_rows(const T* rows, int rows_stride, T* target_origin, PixelRect tile, int target_stride, bool stream) {
    static_assert(sizeof(T) == 4);
    store_tile_rows(static_cast<const void*>(rows), rows_stride, static_cast<void*>(target_origin), tile, target_stride,
                    stream);
}
// One row of store_tile_rows, as it is specified: the values, or `fill` where `covered` (if given)
// has a clear bit.
inline void store_tile_row_reference(const std::uint32_t* from, const std::uint64_t* covered, std::uint32_t fill,
                                     std::uint32_t* to, int width) {
    if (!covered) {
        std::memcpy(to, from, static_cast<std::size_t>(width) * sizeof(std::uint32_t));
        return;
    }
    for (int i = 0; i < width; ++i) to[i] = (*covered >> i) & 1 ? from[i] : fill;
}

// Sets `count` 4-byte words from `to` to `value`, with cached stores: a worker's own tile buffers
// (TileBuffers::begin). In the widest vectors the CPU has (SIMD, tile_store_simd.cpp); code outside
// the kernels is compiled for the baseline's 16-byte vectors.
void fill_words(void* to, std::size_t count, std::uint32_t value);

// Fills a rectangle of at most one tile with one colour and depth; with `stream`, past the caches (see
// store_tile_rows), for a rectangle this draw reads no more.
void fill_rect(TargetView target, PixelRect r, Rgba8 colour, float depth, bool stream);

}  // namespace facet::detail
