// The icosphere the Measure filter stretches into the fitted ellipsoid it draws.
#pragma once

#include "core/types.h"

namespace geofilter {

// Icosahedron subdivided `levels` times (each level splits every triangle in four) and
// projected on the sphere of `radius`: 10 * 4^levels + 2 vertices, nearly regular.
Mesh icosphere(int levels, double radius = 1.0);

} // namespace geofilter
