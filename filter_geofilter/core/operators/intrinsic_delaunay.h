// The intrinsic Delaunay cotangent Laplacian (Bobenko & Springborn 2007; Fisher et al. 2006).
// On a noisy or irregular mesh some triangles have obtuse angles whose cotangents make edge
// weights negative: the operator then is no longer a diffusion, and a filter built on it can
// fold faces. Flipping edges intrinsically (on edge lengths only, the vertices and the surface
// unchanged) until every edge is locally Delaunay makes every weight non-negative and keeps
// the Laplace-Beltrami limit.
#pragma once

#include "core/operators/laplace.h"

namespace geofilter {

struct IntrinsicDelaunayStats {
    int flips = 0;
    int non_delaunay_edges_left = 0;  // only when the flip cap was reached (degenerate input)
};

// K (with the linear-FEM 1/2, as cotan_laplacian) and the lumped mass (a third of the
// intrinsic triangles' areas around each vertex; the total area is that of the input) of the
// intrinsic Delaunay triangulation of the mesh. Boundary and non-manifold edges are never
// flipped. Expects faces of positive area (prepare_mesh removes the others).
Laplacian intrinsic_delaunay_laplacian(const Points& points, const Triangles& triangles,
                                       IntrinsicDelaunayStats* stats = nullptr);

} // namespace geofilter
