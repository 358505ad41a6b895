// Procedural meshes with known geometry, for the tests, the benchmark and the fuzzers.
#pragma once

#include "core/feature/icosphere.h"
#include "core/mesh/subdivide.h"

#include <vector>

namespace geofilter {

// (icosphere and subdivide are the production ones: core/feature/icosphere.h, core/mesh/subdivide.h.)

// Tetrahedron subdivided the way icosphere is and projected on the sphere.
// A mesh from vertex and face lists.
Mesh mesh_from_lists(const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& f);
// `levels` midpoint subdivisions, then every vertex moved radially onto the sphere of `radius`.
Mesh subdivide_onto_sphere(Mesh mesh, int levels, double radius);
Mesh tetrasphere(int levels, double radius = 1.0);
// Latitude/longitude sphere with `rings` latitude bands and `segments` meridians.
Mesh uv_sphere(int rings, int segments, double radius = 1.0);
// Open tube of `radius` along z, from -length/2 to length/2.
Mesh cylinder(int rings, int segments, double radius, double length);
// Torus with the given radii, `rings` around the tube's axis, `segments` around the tube.
Mesh torus(int rings, int segments, double major_radius, double minor_radius);
// Flat square [-size/2, size/2]^2 in the z = 0 plane, (n+1)^2 vertices.
Mesh grid(int n, double size);

// `count` points spread evenly over a sphere of `radius` (the Fibonacci spiral): a cloud.
Points fibonacci_sphere(int count, double radius);

// Moves each vertex along its radial direction by amplitude * unit noise (seeded, deterministic).
void perturb_radially(Mesh& mesh, double amplitude, unsigned seed);
// The mesh's vertices moved along their (area-weighted) normals by Gaussian noise of standard
// deviation sigma (seeded, deterministic): the sampling noise Denoise is measured on.
Points noised_along_normals(const Mesh& mesh, double sigma, unsigned seed);

} // namespace geofilter
