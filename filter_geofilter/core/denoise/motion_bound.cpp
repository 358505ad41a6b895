#include "core/denoise/motion_bound.h"

namespace geofilter {

Points bound_motion(const Points& input, const Points& moved, double bound, MotionBoundReport* report) {
    Points out = moved;
    MotionBoundReport r;
    r.bound = bound;
    for (Eigen::Index v = 0; v < input.rows(); ++v) {
        const Eigen::RowVector3d motion = moved.row(v) - input.row(v);
        const double length = motion.norm();
        if (!(length > bound)) continue;
        out.row(v) = input.row(v) + (bound / length) * motion;
        ++r.vertices_held;
    }
    if (report) *report = r;
    return out;
}

} // namespace geofilter
