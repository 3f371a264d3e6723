// facet bin: the front end of point and line draws. In: projected vertices and the draw's point or
// segment indices. Each point becomes the rectangles of whole pixels it covers (round: runs of rows;
// square: one), each one flat record binned by the Emitter; each segment a quad around it (lines
// clipped in clip space first), one record of its four edges (raster/segment.hpp), or two triangles
// when the quad is not strictly convex. Binning and the tiles are the triangles'.
// Does not shade, and knows nothing of the tiles.
#pragma once

#include <cstddef>

#include "bin/emitter.hpp"
#include "geometry/clip.hpp"

namespace facet::detail {

// Points [first, end) of the draw. Params: the emitter's, with culling off.
template <bool Primitives>
void assemble_points(const ClipVertices& vertices, const DrawInput& input, std::size_t first, std::size_t end,
                     const FrontEndParams& p, Emitter<Primitives>& emitter, FrontEndChunk& out);

// Segments [first, end) of the draw.
template <bool Primitives>
void assemble_lines(const ClipVertices& vertices, const DrawInput& input, std::size_t first, std::size_t end,
                    const FrontEndParams& p, Emitter<Primitives>& emitter, FrontEndChunk& out,
                    const ClipPassVaryings* passes);

}  // namespace facet::detail
