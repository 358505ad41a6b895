#include "core/mesh/seams.h"
#include "core/mesh/boundary.h"

#include <algorithm>
#include <numeric>

namespace geofilter {

std::vector<int> order_by_position(const Points& points) {
    std::vector<int> order(static_cast<std::size_t>(points.rows()));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        for (int k = 0; k < 3; ++k)
            if (points(a, k) != points(b, k)) return points(a, k) < points(b, k);
        return a < b;
    });
    return order;
}

SeamWeld weld_seams(const Points& points, const Triangles& triangles) {
    SeamWeld out{triangles, std::vector<int>(static_cast<std::size_t>(points.rows())), 0};
    std::iota(out.representative.begin(), out.representative.end(), 0);
    if (!points.allFinite() || (triangles.size() > 0 && (triangles.minCoeff() < 0 || triangles.maxCoeff() >= points.rows())))
        return out;
    // Positions first: most meshes have no two vertices in one place, and then the edges
    // (a sort of three per face) are never looked at.
    const std::vector<int> order = order_by_position(points);
    const auto same_place = [&](std::size_t i, std::size_t j) { return points.row(order[i]) == points.row(order[j]); };
    bool any = false;
    for (std::size_t i = 1; i < order.size() && !any; ++i) any = same_place(i - 1, i);
    if (!any) return out;
    const std::vector<bool> on_boundary = boundary_vertices(triangles, points.rows());
    for (std::size_t i = 0; i < order.size();) {
        std::size_t j = i + 1;
        while (j < order.size() && same_place(i, j)) ++j;
        int first = -1;  // the group's lowest-numbered vertex on an open edge
        for (std::size_t k = i; k < j; ++k)
            if (on_boundary[static_cast<std::size_t>(order[k])]) {
                if (first < 0) {
                    first = order[k];
                } else {
                    out.representative[static_cast<std::size_t>(order[k])] = first;
                    ++out.welded;
                }
            }
        i = j;
    }
    if (out.welded)
        for (Eigen::Index f = 0; f < out.triangles.rows(); ++f)
            for (int k = 0; k < 3; ++k) out.triangles(f, k) = out.representative[static_cast<std::size_t>(out.triangles(f, k))];
    return out;
}

} // namespace geofilter
