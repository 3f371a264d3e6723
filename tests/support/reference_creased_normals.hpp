// Test support: the original, sort-based compute_creased_normals, which the faster one in
// src/scene/mesh.cpp must match bit for bit.
#pragma once

#include "facet/mesh.hpp"

namespace facet_test {

void reference_creased_normals(facet::Mesh& mesh, float crease_angle_radians);

}  // namespace facet_test
