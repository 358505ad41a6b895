// What the benchmarks share: the clock, the process's peak memory, the unit-diagonal frame
// their filter designs are given in, and the 1M-vertex torus they all measure on.
#pragma once

#include "core/types.h"
#include "shapes.h"

#include <sys/resource.h>

#include <chrono>

namespace geofilter::benchmark {

inline double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

inline double peak_rss_mib() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss / 1024.0;
}

// Centred, scaled to unit bounding-box diagonal.
inline void normalise(Mesh& m) {
    const Eigen::RowVector3d lo = m.points.colwise().minCoeff(), hi = m.points.colwise().maxCoeff();
    m.points = (m.points.rowwise() - 0.5 * (lo + hi)) / (hi - lo).norm();
}

inline Mesh perturbed_torus_1m() {
    Mesh m = torus(1000, 1000, 1.0, 0.4);
    perturb_radially(m, 0.0005, 23);
    return m;
}

}  // namespace geofilter::benchmark
