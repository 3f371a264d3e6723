// facet tile pass: a worker's tile buffers (tile_buffers.hpp): starting a tile, the shading records
// of the triangles its depth pass lists, ending the depth pass, and writing the colour back.
#include "tile/tile_buffers.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <utility>

#include "tile/depth_pass.hpp"
#include "tile/passes.hpp"
#include "tile/tile_store.hpp"

namespace facet::detail {

void TileBuffers::reserve(std::size_t count, int varyings_, int pass_varyings, std::size_t bins) {
    triangles.reserve(count);
    records.reserve(count * static_cast<std::size_t>(shading_record_floats(varyings_)));
    runs.reserve(bins);
    if (pass_varyings >= 0) {
        pass_stride = pass_record_floats(pass_varyings);
        pass_records.reserve(count * static_cast<std::size_t>(pass_stride));
    }
}

void TileBuffers::begin_owners(PixelRect tile) {
    triangles.clear();
    pass_records.clear();
    for (int r = 0; r < tile.y1 - tile.y0; ++r) std::fill_n(owner + r * k_max_tile_size, tile.x1 - tile.x0, k_none);
}

void TileBuffers::begin(PixelRect tile, int varyings_, TargetView target, const Clear* clear) {
    triangles.clear();
    records.clear();
    runs.clear();
    pass_records.clear();
    varyings = varyings_;
    stride = shading_record_floats(varyings_);
    const int width = tile.x1 - tile.x0, height = tile.y1 - tile.y0;
    depth_cleared = colour_cleared = clear != nullptr;
    if (clear) clear_colour = clear->colour;
    // Whole rows of the arrays, one run each (the columns past a narrower tile are never inside a
    // triangle, and no owner is the safe value there): the widest stores, no loop per row.
    const auto words = static_cast<std::size_t>(height) * k_max_tile_size;
    fill_words(owner, words, k_none);
    if (clear) {
        fill_words(depth, words, std::bit_cast<std::uint32_t>(clear->depth));
        return;
    }
    for (int r = 0; r < height; ++r)
        std::copy_n(target.depth + target.at(tile.x0, tile.y0 + r), width, depth + r * k_max_tile_size);
}

namespace {

// The shading records of the listed triangles [first, end) with N varyings each (N < 0: b.varyings,
// counted at run time), at their ids. A later triangle's varyings are fetched a few triangles ahead,
// since a tile's triangles share vertices with triangles anywhere in the mesh, and its set-up record
// (which names the vertices; no longer in L1 when the depth pass has done the whole tile) further
// ahead. The arrays' addresses and strides are read once, into locals: the records' float stores
// could alias the vectors that hold them.
template <int N>
void write_records(TileBuffers& b, std::size_t first, std::size_t end, const VaryingsSource& source) {
    constexpr std::size_t k_distance = 16, k_record_distance = 32;
    const int n = N >= 0 ? N : b.varyings;
    const std::size_t stride = static_cast<std::size_t>(b.stride);
    const TriangleSetup* const* const triangles = b.triangles.data();
    float* const records = b.records.data();
    const float* const vertices = source.vertices.varyings.data();
    const float* const extras = source.extras.varyings.data();
    const auto vertex_stride = static_cast<std::size_t>(source.vertices.stride);
    const auto extras_stride = static_cast<std::size_t>(source.extras.stride);
    const auto find = [&](const TriangleSetup& t, const float* (&var)[3]) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t ref = t.vertex[k];
            var[k] = (ref & k_clipped_bit) ? extras + (ref & ~k_clipped_bit) * extras_stride : vertices + ref * vertex_stride;
        }
    };
    for (std::size_t i = first; i < end; ++i) {
        const float* var[3];
        if (i + k_record_distance < end) prefetch(&triangles[i + k_record_distance]->vertex);
        if (i + k_distance < end) {
            find(*triangles[i + k_distance], var);
            for (const float* v : var) prefetch(v);
        }
        find(*triangles[i], var);
        write_shading_record(*triangles[i], var, n, records + i * stride);
    }
}

// One write_records per varying count up to k_constant_varyings, where the count is a constant (its
// loop unrolls, as when the records were written by the shader's own template); more, counted at
// run time.
using WriteRecords = void (*)(TileBuffers&, std::size_t, std::size_t, const VaryingsSource&);
constexpr int k_constant_varyings = 16;
template <int... N>
constexpr std::array<WriteRecords, sizeof...(N)> record_writers(std::integer_sequence<int, N...>) {
    return {&write_records<N>...};
}
constexpr auto k_record_writers = record_writers(std::make_integer_sequence<int, k_constant_varyings + 1>{});

}  // namespace

void TileBuffers::write_shading_records(const ClipVertices& vertices) {
    const std::size_t count = triangles.size();
    // The listed triangles before the first that owns a pixel now (end() found it) were hidden
    // everywhere by later ones: a closed mesh's far side, where its bin comes before the near side's,
    // is most of the listed triangles that own nothing in the end (of the 1M sphere's 525k listed,
    // 260k own nothing, 190k of them before the first owner). Their records are never read.
    records.resize(count * static_cast<std::size_t>(stride));
    const WriteRecords write =
        varyings <= k_constant_varyings ? k_record_writers[static_cast<std::size_t>(varyings)] : &write_records<-1>;
    std::uint32_t first = 0;
    for (const BinRun& run : runs) {
        const std::uint32_t from = std::max(first, first_owner);  // k_none: none
        if (from < run.end) write(*this, from, run.end, {vertices, *run.extras});
        first = run.end;
    }
}

void TileBuffers::end(PixelRect tile, TargetView target, bool depth_write, bool store_depth, bool fence) {
    find_owned_pixels(*this, tile);
    if (store_depth && (depth_write || depth_cleared))
        store_tile_rows(depth, k_max_tile_size, target.depth + target.at(tile.x0, tile.y0), tile, target.stride,
                        depth_cleared, nullptr, 0, fence);
}

void TileBuffers::store_colour(PixelRect tile, TargetView target, bool fence) const {
    if (!colour_cleared) return;
    std::uint32_t fill;
    std::memcpy(&fill, &clear_colour, sizeof(fill));
    store_tile_rows(colour, k_max_tile_size, target.colour + target.at(tile.x0, tile.y0), tile, target.stride, true,
                    covered, fill, fence);
}

}  // namespace facet::detail
