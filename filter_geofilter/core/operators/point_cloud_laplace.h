// A Laplace-Beltrami operator for point clouds in the units and with the limit of the mesh's
// cotangent operator (a sphere of radius r: s = 2/r^2 for the coordinate functions), so that a
// filter designed in mesh frequencies means the same on a cloud of the same surface.
#pragma once

#include "core/operators/laplace.h"

#include <vector>

namespace geofilter {

struct PointCloudOptions {
    // Neighbours per point, the candidates for its local triangulation. Its Delaunay 1-ring
    // typically has 6 points; 30 leaves room for uneven sampling without reaching across thin
    // parts of the surface.
    int neighbours = 30;
};

// `neighbours` nearest other points of each point, nearest first (row i: point i's).
using NeighbourTable = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct PointCloudLaplacian {
    Laplacian laplacian;  // K and lumped M, in the conventions of cotan_laplacian
    // Unit normals from each neighbourhood's principal axes, oriented consistently over each
    // connected part of the neighbour graph, most of them pointing away from that part's centroid.
    Points normals;
    NeighbourTable neighbours;
    // Every point's local Delaunay fan, each triangle (centre, a, b) counter-clockwise about
    // the centre's normal: a soup in which most triangles appear three times. Its cotangent K
    // and M are three times `laplacian`'s, so M^-1 K is the same: apply_filter(points,
    // local_triangles, g) filters the cloud with this operator as it stands.
    Triangles local_triangles;
};

// The k nearest other points of every point (a k-d tree). Expects distinct finite points and
// k < number of points.
NeighbourTable nearest_neighbours(const Points& points, int k);

// K and M of the cloud. Throws Error when the cloud has fewer than neighbours + 1 points, a
// non-finite coordinate, exact duplicate points, or a point whose neighbours all lie on a line.
PointCloudLaplacian point_cloud_laplacian(const Points& points, const PointCloudOptions& options = {});

} // namespace geofilter
