#include "core/feature/ellipsoid_view.h"

namespace geofilter {

FeatureEllipsoid shown_ellipsoid(const FeatureEllipsoid& e, double grow, double min_thickness) {
    FeatureEllipsoid shown = e;
    shown.radii = (grow * e.radii).cwiseMax(min_thickness * e.radii.maxCoeff());
    return shown;
}

} // namespace geofilter
