#include "core/denoise/base_level.h"
#include "core/mesh/boundary.h"
#include "core/mesh/components.h"
#include "core/mesh/surface_measures.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace geofilter {

Points to_base_level(const Points& input, const Points& smoothed, const Triangles& triangles, BaseLevelReport* report) {
    const Eigen::MatrixXd normal = vertex_normals(smoothed, triangles);
    std::vector<int> component = connected_components(triangles, smoothed.rows());
    // A component with a boundary vertex is left where it is (label -1).
    const std::vector<bool> on_boundary = boundary_vertices(triangles, smoothed.rows());
    std::vector<bool> open;
    for (Eigen::Index v = 0; v < smoothed.rows(); ++v) {
        const auto c = static_cast<std::size_t>(component[static_cast<std::size_t>(v)]);
        if (open.size() <= c) open.resize(c + 1, false);
        if (on_boundary[static_cast<std::size_t>(v)]) open[c] = true;
    }
    for (int& c : component)
        if (open[static_cast<std::size_t>(c)]) c = -1;
    Eigen::VectorXd area = Eigen::VectorXd::Zero(smoothed.rows());
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        const Eigen::RowVector3d a = smoothed.row(triangles(f, 0));
        const double third = (smoothed.row(triangles(f, 1)) - a).cross(smoothed.row(triangles(f, 2)) - a).norm() / 6;
        for (int k = 0; k < 3; ++k) area[triangles(f, k)] += third;
    }
    // Per component: (removed height, area) of its vertices with a normal.
    std::vector<std::vector<std::pair<double, double>>> heights;
    for (Eigen::Index v = 0; v < smoothed.rows(); ++v) {
        const int c = component[static_cast<std::size_t>(v)];
        if (c < 0 || normal.row(v).squaredNorm() == 0 || !(area[v] > 0)) continue;
        if (heights.size() <= static_cast<std::size_t>(c)) heights.resize(static_cast<std::size_t>(c) + 1);
        heights[static_cast<std::size_t>(c)].emplace_back((input.row(v) - smoothed.row(v)).dot(normal.row(v)), area[v]);
    }
    std::vector<double> offset(heights.size(), 0.0);
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
    for (Eigen::Index v = 0; v < smoothed.rows(); ++v) {
        const int c = component[static_cast<std::size_t>(v)];
        if (c < 0 || static_cast<std::size_t>(c) >= offset.size()) continue;
        out.row(v) += offset[static_cast<std::size_t>(c)] * normal.row(v);
    }
    if (report) *report = r;
    return out;
}

} // namespace geofilter
