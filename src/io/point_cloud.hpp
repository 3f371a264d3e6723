// facet io: point clouds, files of vertices without faces, read by facet itself (assimp reads none of
// these): PLY files whose only non-empty element is `vertex` (ply.cpp's read_ply_point_cloud, which
// hands its arrays here), XYZ and PTS text, and OBJ files with `v` lines only. In: the file's bytes.
// Out: a Scene of one object whose Mesh::points name every vertex with a finite position (the others
// dropped with a warning), with the file's colours and normals when it has them. Not triangle meshes.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "facet/model.hpp"

namespace facet::io_detail {

// What a reader found: positions, and per position a normal and a colour when the file has them.
struct PointCloud {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  // empty, or one per position
    std::vector<Vec4> colours;  // empty, or one per position, in [0, 1]
};

// The cloud as a LoadedModel: non-finite positions dropped (a warning counts them), normals kept only
// when every one is finite and non-zero (as the assimp path does), the up axis applied; an error when
// no point is left or there are more than options.max_triangles.
Result<LoadedModel> point_cloud_model(const std::string& path, PointCloud cloud, const LoadOptions& options);

// XYZ ("x y z" per line, or "x y z nx ny nz") and PTS (an optional first line with the count, then
// "x y z", "x y z intensity" or "x y z intensity r g b" with r, g, b in 0..255); blank lines and
// lines starting with '#' or "//" are skipped. Every point line has the first one's column count.
// `bytes` is the whole file.
Result<LoadedModel> read_text_points(const std::string& path, std::string_view bytes, bool pts, const LoadOptions& options);

// An OBJ file's `v` lines ("v x y z", or "v x y z r g b" with colours in 0..1, as MeshLab writes)
// as points, for a file with no faces, lines or points of its own (assimp refuses those); nullopt
// when the file has no `v` line either.
std::optional<Result<LoadedModel>> read_obj_points(const std::string& path, std::string_view bytes,
                                                   const LoadOptions& options);

}  // namespace facet::io_detail
