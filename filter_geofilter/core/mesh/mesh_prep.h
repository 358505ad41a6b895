// Turning whatever mesh a user has into something the Laplacian is defined on, or
// refusing with a message that names the problem.
#pragma once

#include "core/types.h"

#include <string>
#include <vector>

namespace geofilter {

// The part of a mesh the filter acts on: vertices touched by at least one usable face,
// renumbered compactly. Everything else stays where it is.
struct PreparedMesh {
    Points points;                   // compact copy of the active vertices
    Triangles triangles;             // usable faces, in compact numbering
    std::vector<int> active_vertex;  // compact index -> input vertex index
    int degenerate_faces = 0;        // skipped: zero area (cotangents undefined)
    int isolated_vertices = 0;       // referenced by no usable face: left in place
    int duplicated_vertices = 0;     // active vertices sharing another's exact position
    std::vector<std::string> warnings;
};

// Whether the cotangent weights of triangle (a, b, c), with corner indices i, j, k, are
// defined: three distinct corners and an area not lost to rounding against its longest edge.
bool usable_face(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b, const Eigen::RowVector3d& c, long i, long j,
                 long k);

// Refuses: no vertices, no faces, out-of-range indices, non-finite coordinates, and a mesh
// whose every face is degenerate. Repairs with a warning: zero-area faces are skipped and
// vertices left without a face stay where they are.
// Throws Error naming the first vertex with a NaN or infinite coordinate.
void check_finite_points(const Points& points);

PreparedMesh prepare_mesh(const Points& points, const Triangles& triangles);

} // namespace geofilter
