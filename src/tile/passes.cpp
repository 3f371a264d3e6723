// facet tile pass: the render passes of a draw (passes.hpp): the pass vertex stage, the pass
// records of a tile's listed triangles, and the pixels of its passes. Scalar code: per visible
// pixel it does what fragment_at does for the varyings (the same planes, the same operations in
// the same order, so the normal pass is bit for bit the normal the `normals` shading colours).
#include "tile/passes.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "facet/detail/fragment.hpp"
#include "facet/detail/vertex_stage.hpp"
#include "simd/isa.hpp"
#include "tile/tile_buffers.hpp"
#include "tile/tile_store.hpp"

namespace facet::detail {

PassLayout pass_layout(const DrawPasses& p) {
    PassLayout l;
    if (p.targets.normal) {
        if (p.normals) {
            l.normal_at = l.count;
            l.count += 3;
        } else {
            l.face_normals = true;
        }
    }
    if (p.targets.uv && p.uvs) {
        l.uv_at = l.count;
        l.count += 2;
    }
    const Mat3 identity;
    for (int c = 0; c < 3; ++c) l.rotate_normals |= !(p.normal_space.col[c] == identity.col[c]);
    return l;
}

void run_pass_vertex_stage(const DrawPasses& p, const PassLayout& l, std::size_t begin, std::size_t end,
                           ClipVertices& out) {
    if (l.count == 0) return;
    const std::size_t n = end - begin, stride = static_cast<std::size_t>(l.count);
    float* dst = out.varyings.data() + begin * stride;
    if (l.normal_at >= 0) transform_directions(p.normal_to_world, p.normals + begin, n, dst + l.normal_at, stride);
    if (l.uv_at >= 0)
        for (std::size_t j = 0; j < n; ++j) {
            dst[j * stride + static_cast<std::size_t>(l.uv_at)] = p.uvs[begin + j].x;
            dst[j * stride + static_cast<std::size_t>(l.uv_at) + 1] = p.uvs[begin + j].y;
        }
}

namespace {

// The normal out of the front face of the draw's triangle `primitive`, in world space: the
// rasterizer sees the world-space positions, so their winding says which side is the front.
Vec3 face_normal(const PassDraw& d, std::uint32_t primitive) {
    const DrawPasses& p = *d.passes;
    Vec3 corner[3];
    for (int k = 0; k < 3; ++k) {
        const std::size_t at = std::size_t{primitive} * 3 + static_cast<std::size_t>(k);
        const std::uint32_t i = d.indices.empty() ? static_cast<std::uint32_t>(at) : d.indices[at];
        corner[k] = transform_point(p.model, p.positions[i]);
    }
    const Vec3 n = normalize(cross(corner[1] - corner[0], corner[2] - corner[0]));
    return d.front_face == FrontFace::ccw ? n : -n;
}

}  // namespace

void write_pass_records(TileBuffers& b, std::size_t first, const PassDraw& d, const FrontEndChunk& chunk,
                        const TileBin& bin, const std::vector<std::uint32_t>& primitives) {
    const int n = d.layout.count;
    const bool face = d.layout.face_normals;
    const std::size_t count = b.triangles.size(), stride = static_cast<std::size_t>(b.pass_stride);
    b.pass_records.resize(count * stride);
    for (std::size_t i = first; i < count; ++i) {
        const TriangleSetup& t = *b.triangles[i];
        const std::uint32_t primitive = primitives[static_cast<std::size_t>(&t - bin.data())];
        float* out = b.pass_records.data() + i * stride;
        std::memcpy(out + ph_primitive, &primitive, sizeof(primitive));
        const Vec3 normal = face && d.topology == Topology::triangles ? face_normal(d, primitive) : Vec3{};
        out[ph_face_x] = normal.x, out[ph_face_y] = normal.y, out[ph_face_z] = normal.z;
        if (n > 0) {
            const float* var[3];
            for (int k = 0; k < 3; ++k) var[k] = varyings_of(t.vertex[k], *d.vertices, chunk.pass_extras);
            write_varying_planes(var, n, out + k_pass_head);
        }
    }
}

namespace {

// The targets' row from pixel `at` on.
PassOut targets_at(const PassTargets& t, std::size_t at) {
    auto at_ = [at](auto* p) { return p ? p + at : nullptr; };
    return {at_(t.alpha), at_(t.depth), at_(t.range), at_(t.normal), at_(t.instance), at_(t.material), at_(t.primitive), at_(t.uv)};
}

// The row buffers of the passes the targets want.
PassOut rows_for(PassRow& r, const PassTargets& t) {
    return {t.alpha ? r.alpha : nullptr,         t.depth ? r.depth : nullptr,         t.range ? r.range : nullptr,
            t.normal ? r.normal : nullptr,       t.instance ? r.instance : nullptr,   t.material ? r.material : nullptr,
            t.primitive ? r.primitive : nullptr, t.uv ? r.uv : nullptr};
}

// Rows [0, height) of `width` pixels from `from` (`rows_stride` pixels apart: 0 repeats one row) to
// pixel `at` of a target `stride` pixels wide, for each pass the targets want; `components` 4-byte
// values per pixel. Not fenced: the caller calls fence_streams().
void store_rows(const PassOut& from, int rows_stride, const PassTargets& t, std::size_t at, int width, int height,
                int stride, bool stream) {
    for_each_pass(from, targets_at(t, at), [&](const void* rows, void* target, int components) {
        if (!target) return;
        const PixelRect r{0, 0, width * components, height};
        store_tile_rows(rows, rows_stride * components, target, r, stride * components, stream, nullptr, 0, false);
    });
}

}  // namespace

void fill_pass_background(const PassOut& o, int begin, int end) {
    const int n = end - begin;
    if (n <= 0) return;
    if (o.alpha) std::fill_n(o.alpha + begin, n, 0.0f);
    if (o.depth) std::fill_n(o.depth + begin, n, k_background_depth);
    if (o.range) std::fill_n(o.range + begin, n, k_background_depth);
    if (o.normal) std::fill_n(o.normal + begin, n, Vec3{});
    if (o.instance) std::fill_n(o.instance + begin, n, 0u);
    if (o.material) std::fill_n(o.material + begin, n, 0u);
    if (o.primitive) std::fill_n(o.primitive + begin, n, 0u);
    if (o.uv) std::fill_n(o.uv + begin, n, Vec2{});
}

void write_pass_pixel(const VisibleTile& tile, const float* records, int record_stride, const PassDraw& d, int r,
                      int i, const PassOut& out) {
    const DrawPasses& p = *d.passes;
    const PassLayout& l = d.layout;
    const int n = l.count, x = tile.rect.x0 + i, y = tile.rect.y0 + r;
    const std::uint32_t owner = tile.owner[r * VisibleTile::k_row + i];
    const TriangleSetup& t = *tile.triangles[owner];
    const float* record = records + static_cast<std::size_t>(owner) * static_cast<std::size_t>(record_stride);
    // As fragment_at: the pixel centre relative to vertex 0, q = 1/w, the barycentrics.
    const float px = static_cast<float>(x) + 0.5f, py = static_cast<float>(y) + 0.5f;
    const float dx = px - t.x0, dy = py - t.y0;
    const float q = t.q0 + t.dqdx * dx + t.dqdy * dy;
    const float w = 1.0f / q;
    if (out.alpha) out.alpha[i] = 1.0f;
    if (out.depth || out.range) {
        const float depth = p.depth_scale == 0 ? w : p.depth_offset + p.depth_scale * depth_at(t, x, y);
        if (out.depth) out.depth[i] = depth;
        if (out.range) {
            const float a = p.ray[0] + p.ray[1] * px + p.ray[2] * py;
            const float b = p.ray[3] + p.ray[4] * px + p.ray[5] * py;
            out.range[i] = depth * std::sqrt(1.0f + a * a + b * b);
        }
    }
    float b1 = 0, b2 = 0;
    if (n > 0) {
        b1 = (0.0f + t.dl1dx * dx + t.dl1dy * dy) * w;
        b2 = (0.0f + t.dl2dx * dx + t.dl2dy * dy) * w;
    }
    const float *v0 = record + k_pass_head, *d1 = v0 + n, *d2 = v0 + 2 * n;
    auto varying = [&](int k) { return v0[k] + b1 * d1[k] + b2 * d2[k]; };
    if (out.normal) {
        Vec3 normal{record[ph_face_x], record[ph_face_y], record[ph_face_z]};
        if (l.normal_at >= 0)
            normal = normalize(Vec3{varying(l.normal_at), varying(l.normal_at + 1), varying(l.normal_at + 2)});
        out.normal[i] = l.rotate_normals ? p.normal_space * normal : normal;
    }
    if (out.uv) out.uv[i] = l.uv_at >= 0 ? Vec2{varying(l.uv_at), varying(l.uv_at + 1)} : Vec2{};
    if (out.instance) out.instance[i] = p.instance;
    if (out.material) out.material[i] = p.material;
    if (out.primitive) {
        std::uint32_t primitive;
        std::memcpy(&primitive, record + ph_primitive, sizeof(primitive));
        out.primitive[i] = primitive + 1;
    }
}

void write_pass_pixels(const VisibleTile& tile, const float* records, int record_stride, const PassDraw& d,
                       PassRow* rows) {
    const PassTargets& targets = d.passes->targets;
    const int width = tile.rect.x1 - tile.rect.x0;
    const bool scalar = use_scalar_kernels();
    for (int y = tile.rect.y0; y < tile.rect.y1; ++y) {
        const int r = y - tile.rect.y0;
        const std::uint64_t mask = tile.covered[r];
        const std::size_t row_at = static_cast<std::size_t>(y) * static_cast<std::size_t>(d.stride) + static_cast<std::size_t>(tile.rect.x0);
        if (!rows && !mask) continue;
        const PassOut out = rows ? rows_for(*rows, targets) : targets_at(targets, row_at);
        if (!mask || scalar) {
            if (rows) fill_pass_background(out, 0, width);
            for (std::uint64_t m = mask; m; m &= m - 1) write_pass_pixel(tile, records, record_stride, d, r, std::countr_zero(m), out);
        } else {
            const PassOut direct = targets_at(targets, row_at);
            if (write_pass_row(tile, records, record_stride, d, r, mask, out, rows != nullptr, rows ? &direct : nullptr))
                continue;
        }
        if (rows) store_rows(out, 0, targets, row_at, width, 1, d.stride, true);
    }
    if (rows) fence_streams();
}

void clear_pass_targets(const PassTargets& t, PixelRect r, int stride, bool stream) {
    PassRow background;
    const PassOut row = rows_for(background, t);
    fill_pass_background(row, 0, k_max_tile_size);
    for (int x = r.x0; x < r.x1; x += k_max_tile_size) {
        const int width = std::min(k_max_tile_size, r.x1 - x);
        const std::size_t at = static_cast<std::size_t>(r.y0) * static_cast<std::size_t>(stride) + static_cast<std::size_t>(x);
        store_rows(row, 0, t, at, width, r.y1 - r.y0, stride, stream);
    }
    if (stream) fence_streams();
}

}  // namespace facet::detail
