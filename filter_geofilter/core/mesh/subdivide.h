// Midpoint subdivision: every triangle split in four, the midpoint of a shared edge shared.
#pragma once

#include "core/types.h"

namespace geofilter {

// Positions are not smoothed: the surface stays exactly the same, with four times the faces.
Mesh subdivide(const Mesh& mesh);

} // namespace geofilter
