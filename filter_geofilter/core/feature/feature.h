// Feature measurement (paper section 6): fit an ellipsoid to the selected faces and turn
// its size into a filter frequency.
#pragma once

#include "core/types.h"

#include <string>
#include <vector>

namespace geofilter {

enum class FeatureShape { Sphere, Cylinder };

struct FeatureEllipsoid {
    Eigen::Vector3d center;        // centre of the bounding box in the principal frame
    Eigen::Matrix3d axes;          // columns: principal directions, largest extent first
    Eigen::Vector3d radii;         // half-extents of the bounding box along `axes`, descending
    double radius = 0;             // the feature radius r used for the frequency (see below)
    double area = 0;               // total area of the selection
    int face_count = 0;
    int point_count = 0;           // a cloud's selected points (measure_feature_of_points); face_count is then 0

    // "12 selected faces" or "40 selected points", for messages.
    std::string selection_size() const {
        return point_count > 0 ? std::to_string(point_count) + " selected points"
                               : std::to_string(face_count) + " selected faces";
    }

    // Sphere-like feature: s = 2 / r^2; cylinder-like feature: s = 1 / r^2 (paper section 6).
    double frequency(FeatureShape shape) const {
        return (shape == FeatureShape::Sphere ? 2.0 : 1.0) / (radius * radius);
    }
};

// Area-weighted covariance of the selected faces (exact second moments of the triangles),
// its eigenvectors as the frame, the bounding box of the selected faces' vertices in that
// frame, and radii = the box's half-extents.
//
// The feature radius r (feature_radius) blends the means of the two adjacent pairs of
// radii, weighted by how round each pair is. A round feature has a round cross-section:
//   - a whole sphere: all three radii equal r;
//   - a bump or cap: the two wide extents (the third is its height);
//   - a tube around a cylinder (leg, finger): the two narrow extents (the third is its length).
// In between, r moves continuously with the radii (no switch from one pair to the other).
// Refuses an empty selection, a selection of zero area and out-of-range face indices.
FeatureEllipsoid measure_feature(const Points& points, const Triangles& triangles, const std::vector<int>& selected_faces);

// measure_feature for a point cloud's selected points (`selected_points`, indices into
// `points`), each weighted by the area it stands for (`point_area`, the lumped mass M of the
// cloud's Laplacian). Weighting by area rather than uniformly makes the covariance estimate the
// same surface integral as measure_feature's, so a feature sampled densely on one side and
// sparsely on the other is not tilted towards the dense side; the radii follow the same rule
// (the selected points' bounding box in the principal frame, then feature_radius), so a cloud
// of a mesh's vertices measures like the mesh's faces over them. Refuses an empty selection,
// out-of-range indices, a selection of zero area and one whose points lie on a line.
FeatureEllipsoid measure_feature_of_points(const Points& points, const std::vector<int>& selected_points,
                                           const Eigen::VectorXd& point_area);

// measure_feature in steps, for a selection split over several parts (geofilter-mpi's ranks):
// the moments of each part add up, the frame follows from their sum, the extents in that
// frame combine by min and max.
struct SelectionMoments {
    double area = 0;
    Eigen::Vector3d first = Eigen::Vector3d::Zero();   // integral of (x - origin)
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // integral of (x - origin)(x - origin)^T
    int face_count = 0;
};
// Moments about `origin`, which should lie near the selection (on a georeferenced scan,
// coordinates ~1e6, moments about 0 of a 5 cm feature cancel to rounding noise).
SelectionMoments selection_moments(const Points& points, const Triangles& triangles, const std::vector<int>& faces,
                                   const Eigen::Vector3d& origin);
struct FeatureFrame {
    Eigen::Matrix3d axes;  // principal directions of the covariance, largest spread first
    Eigen::Vector3d mean;  // area-weighted centroid, relative to the moments' origin
};
FeatureFrame feature_frame(const SelectionMoments& total);
// Widens [low, high] to the selected faces' vertices, in the frame's coordinates.
void extend_in_frame(const FeatureFrame& frame, const Eigen::Vector3d& origin, const Points& points,
                     const Triangles& triangles, const std::vector<int>& faces, Eigen::Vector3d& low, Eigen::Vector3d& high);
FeatureEllipsoid ellipsoid_in_frame(const SelectionMoments& total, const FeatureFrame& frame, const Eigen::Vector3d& origin,
                                    const Eigen::Vector3d& low, const Eigen::Vector3d& high);

// With radii r1 >= r2 >= r3 >= 0: w (r1 + r2)/2 + (1 - w)(r2 + r3)/2, where
// w = ln(r2/r3) / (ln(r1/r2) + ln(r2/r3)) (1/2 when both logarithms vanish, 1 when r3 = 0).
// Continuous in the radii; equals r on a sphere (r, r, r), a cap (r, r, h) and a tube (L, r, r).
double feature_radius(const Eigen::Vector3d& radii);

} // namespace geofilter
