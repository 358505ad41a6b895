// Where a flat lowpass leaves a pattern's base surface.
#pragma once

#include "core/types.h"

namespace geofilter {

struct BaseLevelReport {
    double largest_offset = 0;  // largest |offset| applied to a component, in the mesh's units
};

// A lowpass keeps a surface's mean height, and a pattern of bumps of one sign pulls that mean
// towards itself: dents covering a third of a torus leave its lowpass below the undented
// surface, by the dents' mean depth. Where the pattern covers less than half of the surface,
// the rest is the base, and there what the lowpass removed along the normals is that offset:
// its median, weighted by area, over each connected component. Each closed component of
// `smoothed` is moved along its vertex normals by its median of (input - smoothed) . n, so a
// pattern of mixed signs, whose median is near zero, stays where the lowpass put it. A
// component that is not closed (closed_components) is not moved: Denoise holds a boundary
// where it is for a selected bump (denoise_bump_holds_boundary), and that fixes its level.
// Vertices in no face are never moved.
Points to_base_level(const Points& input, const Points& smoothed, const Triangles& triangles,
                     BaseLevelReport* report = nullptr);

} // namespace geofilter
