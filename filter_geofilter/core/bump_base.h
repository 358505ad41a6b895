// Removing a pattern of bumps down to the surface they stand on. A lowpass removes what
// varies between bumps but keeps the pattern's average height, a low-frequency offset: after
// filtering a surface covered with outward bumps, it lies above the surface the bumps stand
// on (on the measured spheres of docs/results.md section 4, +0.3 to +2.6 % in volume). The
// bumps' base is visible between them: there the input lies below the filtered surface by
// that offset. A morphological opening of the input's height above the filtered surface
// (lowest value within the bump-removal radius, then highest of those, then averaged) follows
// that base; moving the filtered surface onto it removes the offset and keeps everything the
// lowpass kept. The selected bump says which side the bumps are on.
#pragma once

#include "types.h"

#include <vector>

namespace geofilter {

struct BumpBaseReport {
    int side = 0;               // +1: the selected bump points outwards (along the normals), -1: inwards, 0: undecided
    double mean_offset = 0;     // area-weighted mean distance the surface moved onto the base
    double largest_offset = 0;  // the largest such distance
};

// `filtered` is the lowpass of `input` (same triangles); `bump_faces` the selected bump;
// `radius` the radius below which bumps were removed (the lowpass's cutoff radius). Vertices
// touched by no face stay where `filtered` has them. Moves the surface only towards the
// base, never away from it. Throws Error on an empty selection or a non-positive radius.
Points lower_onto_bump_base(const Points& input, const Points& filtered, const Triangles& triangles,
                            const std::vector<int>& bump_faces, double radius, BumpBaseReport* report = nullptr);

} // namespace geofilter
