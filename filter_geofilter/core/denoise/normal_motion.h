// Keeping only the part of a smoother's motion that crosses the surface.
#pragma once

#include "core/types.h"

namespace geofilter {

// Noise that moved the vertices along the surface normals left their positions across the
// surface right; a lowpass still moves them sideways (towards the centroid of their
// neighbours on irregular sampling), and that drift is pure error against the scan. Measured
// on 15 scans noised along the normals (docs/results.md section 4), dropping it lowered the
// RMS vertex error by 0.2-43 %. Alone it also folds triangles the lowpass had kept flat (the
// sideways motion was what evened out thin triangles; up to 8x the input's folds), so a
// face turned by more than this angle from the lowpass's sends its vertices back to the
// lowpass's positions, repeated until no face is turned that far. At 30 degrees the output
// folded within two faces of the lowpass alone on those 15 scans while keeping nearly all of
// the gain (at 90 degrees, a fold's own definition, more folds got through: 4 against 0).
constexpr double normal_motion_max_turn_degrees = 30.0;

struct NormalMotionReport {
    int vertices_projected = 0;   // moved along their normal only
    int vertices_kept_smoothed = 0;  // kept the smoother's position (their faces turned too far, or no normal)
    int rounds = 0;               // passes of the turned-face check
};

// Each vertex moved from `input` by the part of (smoothed - input) along the smoothed mesh's
// unit vertex normal (area-weighted), except where that turns a face by more than
// `max_turn_degrees` from the same face in `smoothed`: there the face's vertices take their
// `smoothed` positions. Vertices without a normal (in no face, or only in faces of zero
// area) take their `smoothed` position. Faces of zero area on either side are never counted
// as turned.
Points keep_normal_motion(const Points& input, const Points& smoothed, const Triangles& triangles,
                          double max_turn_degrees = normal_motion_max_turn_degrees,
                          NormalMotionReport* report = nullptr);

} // namespace geofilter
