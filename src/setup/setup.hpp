// facet setup: from a clipped triangle to a TriangleSetup.
// In: three projected, snapped vertices (geometry/project.hpp). Steps: cull by the winding the
// viewer sees, orient counter-clockwise in screen space, edge functions with the top-left rule,
// attribute planes.
// Out: TriangleSetup, or nothing when the triangle is culled, has zero area or covers no pixel centre.
// setup_triangles does the same for a batch of unclipped triangles at once (setup_simd.cpp, SIMD).
#pragma once

#include <cstdint>
#include <cstring>
#include <optional>

#include "facet/detail/front_end.hpp"

namespace facet::detail {

enum class SetupResult { ok, culled, empty };

// `ref` names each vertex's varyings (a ClipVertices index, or k_clipped_bit | extras index).
SetupResult setup_triangle(const ScreenVertex (&v)[3], const std::uint32_t (&ref)[3], const FrontEndParams& params,
                           TriangleSetup& out);

// Up to k_capacity triangles, in submission order, to be set up together. The vertices are stored per
// corner (v[k][i] is corner k of triangle i) so that the kernel loads each corner of a group of
// triangles with one deinterleaving load.
struct SetupBatch {
    static constexpr int k_capacity = 16;  // a multiple of every ISA's number of double lanes
    ScreenVertex v[3][k_capacity];
    std::uint32_t ref[3][k_capacity];
    int count = 0;
};

struct BatchSetupCounts {
    int written;  // records written
    int culled;   // triangles culled (zero area or facing away), as SetupResult::culled
};

// Sets up triangles [0, batch.count) as setup_triangle does each, bit for bit, and writes the records of
// those that survive to out[0, written) in batch order. `out` has room for batch.count records.
BatchSetupCounts setup_triangles(const SetupBatch& batch, const FrontEndParams& params, TriangleSetup* out);

// The two halves of setup_triangles, for a caller that writes each record straight to where it goes
// (the front end: into its tile's bin) rather than to an array it then copies from.
// The SIMD kernel's results, one entry per batch triangle (setup_simd.cpp), read by write_record.
// The record is 32 four-byte words; the kernel stores them already interleaved, four words of each
// triangle to a 16-byte unit (unit[g][i] is words 4g..4g+3 of triangle i's record), so writing a
// record is eight 16-byte copies rather than 32 scalar ones (a third of the front end's time).
struct SetupLanes {
    static constexpr int n = SetupBatch::k_capacity;
    static constexpr int k_units = static_cast<int>(sizeof(TriangleSetup) / 16);
    struct alignas(16) Unit {
        std::uint32_t word[4];
    };
    Unit unit[k_units][n];
    std::uint32_t keep = 0, culled = 0;  // bit i: triangle i
    // The inclusive pixel bounds of triangle i (unit 3: min_x, min_y, max_x, max_y).
    const std::int32_t* bounds(int i) const { return reinterpret_cast<const std::int32_t*>(unit[3][i].word); }
};
// Runs the kernel of the selected ISA on the batch. False when the batch must be set up one by one
// instead (setup_one_by_one): the scalar ISA is selected, or a coordinate is too large to be exact.
bool setup_lanes(const SetupBatch& batch, const FrontEndParams& params, SetupLanes& lanes);
// The record of batch triangle i (a bit of lanes.keep), as setup_triangle writes it.
// (memcpy, not stores through a Unit*: the record is a TriangleSetup, and its bytes are copied.)
inline void write_record(const SetupLanes& lanes, int i, TriangleSetup& t) {
    auto* to = reinterpret_cast<unsigned char*>(&t);
    for (int g = 0; g < SetupLanes::k_units; ++g) std::memcpy(to + 16 * g, lanes.unit[g][i].word, 16);
}
// setup_triangle on each triangle of the batch, the survivors written to out[0, written).
BatchSetupCounts setup_one_by_one(const SetupBatch& batch, const FrontEndParams& params, TriangleSetup* out);

}  // namespace facet::detail
