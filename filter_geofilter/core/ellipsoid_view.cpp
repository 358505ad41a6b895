#include "ellipsoid_view.h"

#include <algorithm>
#include <cmath>

namespace geofilter {

double enclosing_scale(const FeatureEllipsoid& e, const Points& points, const Triangles& triangles,
                       const std::vector<int>& selected_faces, double margin) {
    double worst = 1;  // largest ellipsoidal norm |A^T (p - c) / r| of a selected vertex
    // A flat selection has a zero radius: measure that axis as if it were a hair thick.
    const Eigen::Vector3d radii = e.radii.cwiseMax(1e-9 * std::max(e.radii.maxCoeff(), 1e-300));
    for (int f : selected_faces) {
        if (f < 0 || f >= triangles.rows()) continue;  // measure_feature has refused these already
        for (int k = 0; k < 3; ++k) {
            const Eigen::Vector3d local = e.axes.transpose() * (points.row(triangles(f, k)).transpose() - e.center);
            worst = std::max(worst, local.cwiseQuotient(radii).norm());
        }
    }
    return worst * margin;
}

} // namespace geofilter
