// facet scene: how many triangles, points and line segments a scene holds, and how facet render and
// facet view say it. Counts what the meshes list; does not check or draw anything.
#pragma once

#include <cstddef>
#include <string>

#include "facet/api.hpp"
#include "facet/scene.hpp"

FACET_API_BEGIN
namespace facet {

std::size_t point_count(const Scene& scene);
std::size_t segment_count(const Scene& scene);

// "N triangles", then ", N points" and ", N segments" when there are some ("N points" alone for a
// cloud, never "0 triangles" for one).
std::string describe_primitives(std::size_t triangles, std::size_t points, std::size_t segments);
std::string describe_primitives(const Scene& scene);

}  // namespace facet
FACET_API_END
