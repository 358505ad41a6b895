// The measured feature ellipsoid as it is shown. The fitted ellipsoid (paper
// section 6) touches the surface it measures (its box is the selection's) and, for a flat
// selection, has zero thickness and lies in the surface; drawn in the mesh's grey it cannot
// be told from the mesh. The shown one is the measured one made a little larger (so it
// stands just off the surface where it touches it) and at least a little thick, and the
// adapters colour it. The measured radii and the frequency are not changed.
#pragma once

#include "core/feature/feature.h"

namespace geofilter {

// e with radii max(grow * r_k, min_thickness * r_max).
FeatureEllipsoid shown_ellipsoid(const FeatureEllipsoid& e, double grow = 1.02, double min_thickness = 0.05);

} // namespace geofilter
