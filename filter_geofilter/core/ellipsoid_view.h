// The measured feature ellipsoid as it is shown (issue 11): the fitted ellipsoid (paper
// section 6) is inscribed in the selection's bounding box, so much of it lies under the
// surface it measures. The shown one is scaled about its centre until it encloses every
// selected vertex, so that it wraps the feature like the paper's Fig. 1. The measured radii
// (and the frequency) are not changed.
#pragma once

#include "feature.h"

namespace geofilter {

// The smallest factor k >= 1 such that the ellipsoid with radii k * e.radii contains every
// vertex of `selected_faces`, times `margin` (e.g. 1.02: a little off the surface).
double enclosing_scale(const FeatureEllipsoid& e, const Points& points, const Triangles& triangles,
                       const std::vector<int>& selected_faces, double margin = 1.02);

} // namespace geofilter
