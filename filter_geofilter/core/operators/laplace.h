// Cotangent stiffness and lumped mass of a triangle mesh (paper eq. 1-2, with the
// factor 1/2 of the linear FEM stiffness: see docs/paper-notes.md §1).
#pragma once

#include "core/types.h"

#include <vector>

namespace geofilter {

struct Laplacian {
    SparseMatrix stiffness;  // K: symmetric positive semi-definite, rows sum to zero
    Eigen::VectorXd mass;    // diagonal of M: one third of the area around each vertex
};

// Builds K and M so that -L = M^-1 K and a sphere of radius r has the coordinate
// functions as eigenvectors with eigenvalue 2/r^2. Faces listed in skip_face (if
// non-empty) contribute nothing; a vertex touched by no kept face gets mass 0.
Laplacian cotan_laplacian(const Points& points, const Triangles& triangles,
                          const std::vector<bool>& skip_face = {});

// Kt = M^-1/2 K M^-1/2: symmetric, with the eigenvalues of -L. Requires positive mass.
SparseMatrix mass_normalized_stiffness(const Laplacian& laplacian);

} // namespace geofilter
