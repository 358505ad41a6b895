// The discrete Laplacians a filter can be built on; each gives K and a positive lumped mass
// M so that the filter's frequencies are the eigenvalues of K v = s M v.
#pragma once

#include "core/operators/laplace.h"

namespace geofilter {

enum class Operator {
    // Cotangent weights (paper eq. 1-2): frequencies in 1/length^2, s = 2/r^2 on a sphere.
    Cotangent,
    // Cotangent weights of the intrinsic Delaunay triangulation: same units, weights >= 0.
    IntrinsicDelaunay,
    // Umbrella (graph) Laplacian normalised by the vertex degree, Taubin's operator:
    // K = D - A, M = D. Frequencies are per vertex, in [0, 2], whatever the edge lengths;
    // independent of the noisy positions.
    Umbrella,
};

const char* operator_name(Operator op);

// Whether K and M change with the vertex positions (not for the umbrella: connectivity only).
bool operator_uses_positions(Operator op);

// The umbrella operator of the mesh (K = D - A over its edges, M = the degrees).
Laplacian umbrella_laplacian(const Triangles& triangles, Eigen::Index vertex_count);

// K and M of `op` for a prepared mesh (faces of positive area).
Laplacian build_laplacian(Operator op, const Points& points, const Triangles& triangles);

} // namespace geofilter
