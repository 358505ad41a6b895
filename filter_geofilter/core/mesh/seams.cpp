#include "core/mesh/seams.h"
#include "core/mesh/boundary.h"

#include <algorithm>
#include <numeric>

namespace geofilter {

SeamWeld weld_seams(const Points& points, const Triangles& triangles) {
    SeamWeld out{triangles, std::vector<int>(static_cast<std::size_t>(points.rows())), 0};
    std::iota(out.representative.begin(), out.representative.end(), 0);
    if (!points.allFinite() || (triangles.size() > 0 && (triangles.minCoeff() < 0 || triangles.maxCoeff() >= points.rows())))
        return out;
    const std::vector<bool> on_boundary = boundary_vertices(triangles, points.rows());
    std::vector<int> open;
    for (Eigen::Index v = 0; v < points.rows(); ++v)
        if (on_boundary[static_cast<std::size_t>(v)]) open.push_back(static_cast<int>(v));
    const auto before = [&](int a, int b) {
        for (int k = 0; k < 3; ++k)
            if (points(a, k) != points(b, k)) return points(a, k) < points(b, k);
        return a < b;
    };
    std::sort(open.begin(), open.end(), before);
    for (std::size_t i = 0; i < open.size();) {
        std::size_t j = i + 1;
        while (j < open.size() && points.row(open[j]) == points.row(open[i])) {
            out.representative[static_cast<std::size_t>(open[j])] = open[i];
            ++out.welded;
            ++j;
        }
        i = j;
    }
    if (out.welded)
        for (Eigen::Index f = 0; f < out.triangles.rows(); ++f)
            for (int k = 0; k < 3; ++k) out.triangles(f, k) = out.representative[static_cast<std::size_t>(out.triangles(f, k))];
    return out;
}

} // namespace geofilter
