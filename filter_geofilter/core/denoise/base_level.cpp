#include "core/denoise/base_level.h"
#include "core/mesh/components.h"
#include "core/mesh/surface_measures.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace geofilter {

Points to_base_level(const Points& input, const Points& smoothed, const Triangles& triangles, BaseLevelReport* report) {
    const Eigen::MatrixXd normal = vertex_normals(smoothed, triangles);
    const std::vector<int> component = connected_components(triangles, smoothed.rows());
    const int count = component_count(component);
    const std::vector<bool> closed = closed_components(triangles, component, count);
    const Eigen::VectorXd area = vertex_areas(smoothed, triangles);
    // Per closed component: (removed height, area) of its vertices with a normal.
    std::vector<std::vector<std::pair<double, double>>> heights(static_cast<std::size_t>(count));
    for (Eigen::Index v = 0; v < smoothed.rows(); ++v) {
        const auto c = static_cast<std::size_t>(component[static_cast<std::size_t>(v)]);
        if (!closed[c] || normal.row(v).squaredNorm() == 0 || !(area[v] > 0)) continue;
        heights[c].emplace_back((input.row(v) - smoothed.row(v)).dot(normal.row(v)), area[v]);
    }
    std::vector<double> offset(heights.size(), 0.0);  // 0 for the components left where they are
    BaseLevelReport r;
    for (std::size_t c = 0; c < heights.size(); ++c) {
        auto& h = heights[c];
        if (h.empty()) continue;
        std::sort(h.begin(), h.end());
        double total = 0;
        for (const auto& [height, weight] : h) total += weight;
        double below = 0;
        for (const auto& [height, weight] : h) {
            below += weight;
            if (below >= total / 2) {
                offset[c] = height;
                break;
            }
        }
        r.largest_offset = std::max(r.largest_offset, std::abs(offset[c]));
    }
    Points out = smoothed;
    for (Eigen::Index v = 0; v < smoothed.rows(); ++v)
        out.row(v) += offset[static_cast<std::size_t>(component[static_cast<std::size_t>(v)])] * normal.row(v);
    if (report) *report = r;
    return out;
}

} // namespace geofilter
