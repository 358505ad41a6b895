// Holding a denoiser's motion within what the noise could have moved a vertex.
#pragma once

#include "core/types.h"

namespace geofilter {

struct MotionBoundReport {
    double bound = 0;     // the longest motion allowed, in the mesh's units: the mean over the vertices
    int vertices_held = 0;  // vertices whose motion was longer and was shortened to the bound
};

// Each vertex v of `moved` whose motion from `input` is longer than `bound[v]` is brought back
// along that motion to `bound[v]` from its input position; the others stay where they are.
// A denoiser that moves a vertex much farther than its noise could have displaced it is
// reshaping the surface there (a lowpass shrinking a toe or the tip of a tail), not
// removing noise.
Points bound_motion(const Points& input, const Points& moved, const Eigen::VectorXd& bound, MotionBoundReport* report = nullptr);

} // namespace geofilter
