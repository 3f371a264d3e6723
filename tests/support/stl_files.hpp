// STL files written by the tests: binary and ASCII, from triangles or a mesh.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "facet/mesh.hpp"

namespace facet_test {

using StlTriangle = std::array<facet::Vec3, 3>;

// 80-byte header (`header` padded with NULs), the count, then per facet a zero normal (as many
// exporters write it), the corners and the 16-bit attribute (attributes[i], or 0).
std::string binary_stl(const std::vector<StlTriangle>& triangles, const std::string& header = "",
                       const std::vector<std::uint16_t>& attributes = {});
// "solid name", the facets in the usual indented layout with zero normals, "endsolid name";
// coordinates with 9 significant digits (exact for floats).
std::string ascii_stl(const std::vector<StlTriangle>& triangles, const std::string& name = "test");
// Each triangle of the mesh with its corners' positions.
std::vector<StlTriangle> triangles_of(const facet::Mesh& m);

}  // namespace facet_test
