// facet scene: the contact shadow's blur (contact_shadow.cpp), for its test. In: an n x n image of
// floats, row by row; out: the same image blurred. Nothing else.
#pragma once

#include <vector>

namespace facet::detail {

// Three box filters of radius r along rows then columns (about a Gaussian), clamped at the edges:
// each pass sets every texel to the sum of the 2r + 1 texels around it along the row (then the
// column), added in order from -r to r starting from 0, times 1 / (2r + 1) in float.
void box_blur(std::vector<float>& v, int n, int r);

}  // namespace facet::detail
