// The icosphere: the Measure filter draws the fitted ellipsoid as a scaled one, and the
// midpoint subdivision it is built from. Test meshes (tests/support/shapes.h) build on these.
#pragma once

#include "types.h"

#include <vector>

namespace geofilter {

// Icosahedron subdivided `levels` times (each level splits every triangle in four) and
// projected on the sphere of `radius`: 10 * 4^levels + 2 vertices, nearly regular.
Mesh icosphere(int levels, double radius = 1.0);
// Splits every triangle in four (midpoints shared) without projecting.
Mesh subdivide(const Mesh& mesh);
// `levels` subdivisions, then every vertex moved radially onto the sphere of `radius`.
Mesh subdivide_onto_sphere(Mesh mesh, int levels, double radius);
// A mesh from vertex and face lists.
Mesh mesh_from_lists(const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& f);

} // namespace geofilter
