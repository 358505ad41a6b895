// Open boundaries: which vertices lie on them, and the split of a shape into the part a
// filter may change and the part fixed by the boundary.
#pragma once

#include "core/operators/laplace.h"
#include "core/types.h"

#include <vector>

namespace geofilter {

// A vertex is on the boundary when one of its edges belongs to exactly one face.
std::vector<bool> boundary_vertices(const Triangles& triangles, Eigen::Index vertex_count);

// The harmonic extension h of the boundary positions into the interior: K_II h_I = -K_IB p_B
// (h = p on the boundary). p - h vanishes on the boundary, so it expands in the Dirichlet
// eigenmodes of the interior, which is what a filter with a fixed boundary scales.
// Components without boundary get h = 0 on their vertices. `points` may have any number of
// columns (a field's, filter_field), each extended on its own.
Eigen::MatrixXd harmonic_extension(const Laplacian& laplacian, const std::vector<bool>& on_boundary,
                                   const Eigen::MatrixXd& points);

// K and M restricted to the vertices where `keep` is true (in their order).
Laplacian restrict_laplacian(const Laplacian& laplacian, const std::vector<bool>& keep);

} // namespace geofilter
