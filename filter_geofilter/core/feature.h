// Feature measurement (paper section 6): fit an ellipsoid to the selected faces and turn
// its size into a filter frequency.
#pragma once

#include "types.h"

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

    // Sphere-like feature: s = 2 / r^2; cylinder-like feature: s = 1 / r^2 (paper section 6).
    double frequency(FeatureShape shape) const {
        return (shape == FeatureShape::Sphere ? 2.0 : 1.0) / (radius * radius);
    }
};

// Area-weighted covariance of the selected faces (exact second moments of the triangles),
// its eigenvectors as the frame, the bounding box of the selected faces' vertices in that
// frame, and radii = the box's half-extents.
//
// The feature radius r is the mean of the two half-extents that are closest to each other
// (smallest ratio). A round feature has a round cross-section, and that pair is it:
//   - a whole sphere: all three equal r;
//   - a bump or cap: the two wide extents (the third is its height);
//   - a tube around a cylinder (leg, finger): the two narrow extents (the third is its length);
//   - a short ring of a cylinder: the two wide extents.
// Refuses an empty selection, a selection of zero area and out-of-range face indices.
FeatureEllipsoid measure_feature(const Points& points, const Triangles& triangles, const std::vector<int>& selected_faces);

} // namespace geofilter
