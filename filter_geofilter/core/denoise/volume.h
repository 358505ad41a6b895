// Keeping the enclosed volume of closed surfaces through a smoothing step.
#pragma once

#include "core/types.h"

namespace geofilter {

struct VolumeRestoreReport {
    int closed_components = 0;    // components that enclose a volume (and were restored)
    double largest_change = 0;    // largest relative volume change the smoothing had made (before restoring)
    double largest_offset = 0;    // largest |offset| applied, in the mesh's units
};

// Moves every closed connected component of `smoothed` along its vertex normals by one
// uniform offset so that it encloses the same volume as in `input` (same triangles): a
// smoother removing noise from a thin, curved surface also shrinks it (the man scan lost 0.1
// to 0.5 % in docs/results.md section 4), which no lowpass of the geometry alone undoes. A
// uniform offset is the smallest change of shape that restores the volume (Desbrun et al. 1999
// rescale instead, which moves far parts more). Open components, and closed ones that
// enclose no volume, are left as they are. Vertices in no face are never moved.
Points restore_volume(const Points& input, const Points& smoothed, const Triangles& triangles,
                      VolumeRestoreReport* report = nullptr);

} // namespace geofilter
