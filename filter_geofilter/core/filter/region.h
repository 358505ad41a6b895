// Filtering one region of a mesh with a smooth fade to the untouched rest.
//
// A weight w in [0, 1] per vertex says how much of the filter's change a vertex takes. The
// domain D = {w > 0} is filtered as its own domain with every vertex outside D held where it
// is (the Dirichlet problem of fix_boundary: p' = h + G(L_D)(p - h), h the harmonic extension
// of the fixed ring into D), and then p_final = p + w (p' - p). Only D and the ring of fixed
// vertices around it are assembled and factorised; vertices outside D are copied unchanged.
#pragma once

#include "core/filter/filter.h"
#include "core/types.h"

#include <vector>

namespace geofilter {

// The fade across the blend band: 1 at distance 0, 0 from `width` on, with zero slope at
// both ends (1 - 3t^2 + 2t^3, t = distance / width), so the weight is C1 where the band
// meets the region and where it meets the untouched rest. width = 0 gives a hard cut.
double blend_profile(double distance, double width);

// Weight 1 on the vertices of `faces` (the region), fading by blend_profile of the shortest
// edge-path distance to the region (edges weighted by their length) to 0 at blend_width.
// Only the region and its band are visited. Throws Error on out-of-range face indices.
std::vector<double> region_weight(const Points& points, const Triangles& triangles, const std::vector<int>& faces,
                                  double blend_width);

// p_final = p + w (changed - p) for every vertex: w = 0 keeps p bit for bit, w = 1 takes the
// changed point as is. The blend of apply_filter_weighted, for a change made some other way
// (Denoise's sampling-noise rule). Throws Error unless the sizes agree and w lies in [0, 1].
Points blend_by_weight(const Points& points, const Points& changed, const std::vector<double>& weight);

struct RegionReport {
    int domain_vertices = 0;        // |D|: vertices with w > 0
    int ring_vertices = 0;          // vertices outside D held fixed because they share a face with D
    int free_components = 0;        // connected parts of D with no fixed vertex: filtered as a whole
    int submesh_vertices = 0;       // vertices assembled and solved on (D and its ring)
};

// The filter applied with the weight `weight` (one value in [0, 1] per vertex of `points`;
// refused otherwise). Vertices with w = 0 are returned bit-for-bit as given; with w = 1
// everywhere the result is apply_filter's, bit for bit. Open boundaries inside D follow
// options.fix_boundary as in apply_filter (free by default). A connected part of D with no
// vertex outside D is filtered as apply_filter would filter it alone (about its own centroid).
// `report` receives the solver's report (active_vertices = the vertices of D in usable faces,
// fixed_vertices = open-boundary vertices of D kept by fix_boundary); `region_report` what the
// region turned into. The sub-mesh is filtered by apply_filter_with_held, through `cache` when
// given (MeshLab's Preview of the same region reuses the operator and its factors).
Points apply_filter_weighted(const Points& points, const Triangles& triangles, const TransferFunction& g,
                             const std::vector<double>& weight, const FilterOptions& options = {},
                             FilterReport* report = nullptr, RegionReport* region_report = nullptr,
                             FilterCache* cache = nullptr);

} // namespace geofilter
