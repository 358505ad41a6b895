#include "core/denoise/motion_bound.h"

namespace geofilter {

Points bound_motion(const Points& input, const Points& moved, const Eigen::VectorXd& bound, MotionBoundReport* report) {
    if (bound.size() != input.rows())
        throw Error("the motion bound must be given per vertex (" + std::to_string(input.rows()) + "), not for " +
                    std::to_string(bound.size()));
    Points out = moved;
    MotionBoundReport r;
    r.bound = bound.size() ? bound.mean() : 0.0;
    for (Eigen::Index v = 0; v < input.rows(); ++v) {
        const Eigen::RowVector3d motion = moved.row(v) - input.row(v);
        const double length = motion.norm();
        if (!(length > bound[v])) continue;
        out.row(v) = input.row(v) + (bound[v] / length) * motion;
        ++r.vertices_held;
    }
    if (report) *report = r;
    return out;
}

} // namespace geofilter
