// A Laplace-Beltrami operator for point clouds in the units and with the limit of the mesh's
// cotangent operator (a sphere of radius r: s = 2/r^2 for the coordinate functions), so that a
// filter designed in mesh frequencies means the same on a cloud of the same surface.
#pragma once

#include "core/operators/laplace.h"

#include <vector>

namespace geofilter {

struct PointCloudOptions {
    // Neighbours per point that fit its tangent plane (and orient its normal): enough that the
    // plane averages out noise of a third of the spacing.
    int neighbours = 30;
    // The nearest of them that may join its local triangulation. A Delaunay 1-ring typically
    // has 6 points. Far candidates enter the fan through gaps that noise opens in the
    // projected ring, or from across a thin part (points of the bunny's ears, 3-6 spacings
    // from its head, joined it, and were pulled about 4 times the noise off their surface).
    // On the tuning half of the cloud cases (generalize_denoise --as-clouds) Denoise ended at
    // 0.69 of the input's RMS (geometric mean) with 8 to 15 candidates, 0.70 with 20, 0.72
    // with 30 and with 6. An irregular sampling needs more of them to close its ring: on
    // vertices slid by a quarter spacing the lowpass's distance to the mesh operator's was
    // 3.2 % of its motion with 10, 1.5 % with 12, 0.82 % with 15 and 0.79 % from 18 on. So 15,
    // the largest count of the plateau.
    int fan_candidates = 15;
};

// `neighbours` nearest other points of each point, nearest first (row i: point i's).
using NeighbourTable = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct PointCloudLaplacian {
    Laplacian laplacian;  // K and lumped M, in the conventions of cotan_laplacian
    // Unit normals from each neighbourhood's principal axes, oriented consistently over each
    // connected part of the neighbour graph, most of them pointing away from that part's centroid.
    Points normals;
    NeighbourTable neighbours;
    int fan_candidates = 0;  // the first columns of `neighbours` that the fans were built from
    long fans_from_all_neighbours = 0;  // points whose nearest fan_candidates made no triangle
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
