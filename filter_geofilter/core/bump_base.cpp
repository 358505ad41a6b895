#include "bump_base.h"
#include "components.h"
#include "surface_measures.h"

#include <algorithm>
#include <cmath>

namespace geofilter {

namespace {

// One step of a grey-scale morphology or mean over each vertex's closed 1-ring.
template <class Combine>
Eigen::VectorXd ring_step(const VertexNeighbours& nb, const Eigen::VectorXd& value, const std::vector<bool>& used,
                          Combine combine) {
    Eigen::VectorXd out = value;
    for (Eigen::Index v = 0; v < value.size(); ++v) {
        if (!used[v]) continue;
        double acc = value[v];
        int count = 1;
        for (int j = nb.start[v]; j < nb.start[v + 1]; ++j)
            if (used[nb.index[j]]) {
                acc = combine(acc, value[nb.index[j]]);
                ++count;
            }
        out[v] = combine.finish(acc, count);
    }
    return out;
}

struct Min {
    double operator()(double a, double b) const { return std::min(a, b); }
    double finish(double a, int) const { return a; }
};
struct Max {
    double operator()(double a, double b) const { return std::max(a, b); }
    double finish(double a, int) const { return a; }
};
struct Mean {
    double operator()(double a, double b) const { return a + b; }
    double finish(double a, int count) const { return a / count; }
};

} // namespace

Points lower_onto_bump_base(const Points& input, const Points& filtered, const Triangles& triangles,
                            const std::vector<int>& bump_faces, double radius, BumpBaseReport* report) {
    if (bump_faces.empty()) throw Error("no bump is selected: select one bump of the pattern to remove");
    if (!(radius > 0) || !std::isfinite(radius))
        throw Error("the bump radius must be a positive number (got " + format_number(radius) + ")");
    const Eigen::Index n = filtered.rows();

    // The filtered surface's normals and vertex areas.
    const Eigen::MatrixXd normal = vertex_normals(filtered, triangles);
    Eigen::VectorXd area = Eigen::VectorXd::Zero(n);
    std::vector<bool> used(static_cast<size_t>(n), false);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        const Eigen::RowVector3d a = filtered.row(triangles(f, 0)), b = filtered.row(triangles(f, 1)),
                                 c = filtered.row(triangles(f, 2));
        const double third_of_area = (b - a).cross(c - a).norm() / 6;
        for (int k = 0; k < 3; ++k) {
            area[triangles(f, k)] += third_of_area;
            used[triangles(f, k)] = true;
        }
    }
    const double mean_edge = mean_edge_length(filtered, triangles);
    Eigen::VectorXd height = Eigen::VectorXd::Zero(n);  // of the input above the filtered surface
    for (Eigen::Index v = 0; v < n; ++v) height[v] = (input.row(v) - filtered.row(v)).dot(normal.row(v));

    // The selected bump rises above the filtered surface on the side it points to.
    double bump_height = 0, bump_area = 0;
    for (int f : bump_faces)
        for (int k = 0; k < 3; ++k) {
            bump_height += area[triangles(f, k)] * height[triangles(f, k)];
            bump_area += area[triangles(f, k)];
        }
    BumpBaseReport result;
    result.side = bump_height > 0 ? 1 : bump_height < 0 ? -1 : 0;
    Points out = filtered;
    if (result.side == 0 || !(mean_edge > 0)) {
        if (report) *report = result;
        return out;
    }

    // Opening (erosion then dilation) of the height on the bumps' side, over rings as wide as
    // the removal radius, then a mean over the same width: the base's level, smooth.
    const VertexNeighbours nb = vertex_neighbours(triangles, n);
    const int rings = std::max(1, static_cast<int>(std::lround(radius / mean_edge)));
    Eigen::VectorXd base = result.side * height;
    for (int i = 0; i < rings; ++i) base = ring_step(nb, base, used, Min{});
    for (int i = 0; i < rings; ++i) base = ring_step(nb, base, used, Max{});
    for (int i = 0; i < rings; ++i) base = ring_step(nb, base, used, Mean{});

    double moved_area = 0, total_area = 0;
    for (Eigen::Index v = 0; v < n; ++v) {
        if (!used[v]) continue;
        const double depth = std::min(base[v], 0.0);  // only towards the base
        out.row(v) += result.side * depth * normal.row(v);
        moved_area += area[v] * -depth;
        total_area += area[v];
        result.largest_offset = std::max(result.largest_offset, -depth);
    }
    result.mean_offset = total_area > 0 ? moved_area / total_area : 0.0;
    if (report) *report = result;
    return out;
}

} // namespace geofilter
