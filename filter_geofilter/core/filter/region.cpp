#include "core/filter/region.h"

#include "core/mesh/boundary.h"
#include "core/mesh/components.h"
#include "core/mesh/mesh_prep.h"
#include "core/solve/solvers.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <new>
#include <queue>
#include <utility>

namespace geofilter {

double blend_profile(double distance, double width) {
    if (distance <= 0) return 1;
    if (!(width > 0) || distance >= width) return 0;
    const double t = distance / width;
    return 1 - t * t * (3 - 2 * t);
}

namespace {

void check_faces(const Triangles& triangles, Eigen::Index vertex_count) {
    if (triangles.size() > 0 && (triangles.minCoeff() < 0 || triangles.maxCoeff() >= vertex_count))
        throw Error("a face refers to a vertex that does not exist (index out of range 0.." +
                    std::to_string(vertex_count - 1) + ")");
}

// Exact at both ends: untouched vertices stay bit for bit, and a weight of 1 everywhere is
// the change itself, bit for bit.
Eigen::RowVector3d blended(const Eigen::RowVector3d& original, const Eigen::RowVector3d& changed, double w) {
    if (w == 0) return original;
    if (w == 1) return changed;
    return original + w * (changed - original);
}

void check_weight(const std::vector<double>& weight, Eigen::Index n) {
    if (static_cast<Eigen::Index>(weight.size()) != n)
        throw Error("the weight has " + std::to_string(weight.size()) + " values for " + std::to_string(n) + " vertices");
    for (Eigen::Index v = 0; v < n; ++v)
        if (!(weight[v] >= 0 && weight[v] <= 1))
            throw Error("the weight of vertex " + std::to_string(v) + " is " + format_number(weight[v]) +
                        ": weights must lie in [0, 1]");
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Connected parts of the sub-mesh that nothing holds (no ring vertex, and no open boundary
// when fix_boundary keeps it): whole components of the mesh, filtered about their centroid.
int free_components(const Triangles& triangles, const std::vector<bool>& held, bool fix_boundary) {
    const Eigen::Index n = static_cast<Eigen::Index>(held.size());
    const std::vector<int> label = connected_components(triangles, n);
    const std::vector<bool> boundary = fix_boundary ? boundary_vertices(triangles, n) : std::vector<bool>(held.size());
    std::vector<bool> anchored(static_cast<size_t>(component_count(label)), false);
    for (Eigen::Index v = 0; v < n; ++v)
        if (held[v] || boundary[v]) anchored[label[v]] = true;
    return static_cast<int>(std::count(anchored.begin(), anchored.end(), false));
}

} // namespace

std::vector<double> region_weight(const Points& points, const Triangles& triangles, const std::vector<int>& faces,
                                  double blend_width) {
    const Eigen::Index n = points.rows();
    check_faces(triangles, n);
    if (!(blend_width >= 0) || !std::isfinite(blend_width))
        throw Error("the blend width must be a finite number >= 0 (got " + format_number(blend_width) + ")");
    std::vector<double> distance(static_cast<size_t>(n), std::numeric_limits<double>::infinity());
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    for (int f : faces) {
        if (f < 0 || f >= triangles.rows())
            throw Error("selected face " + std::to_string(f) + " does not exist (the mesh has " +
                        std::to_string(triangles.rows()) + " faces)");
        for (int k = 0; k < 3; ++k) {
            const int v = triangles(f, k);
            if (distance[v] != 0) queue.emplace(distance[v] = 0, v);
        }
    }
    if (blend_width > 0) {
        // Dijkstra from the region, stopped at the band's edge: cost follows the band.
        const VertexNeighbours a = vertex_neighbours(triangles, n);
        while (!queue.empty()) {
            const auto [d, v] = queue.top();
            queue.pop();
            if (d > distance[v]) continue;
            for (int e = a.start[v]; e < a.start[v + 1]; ++e) {
                const int u = a.index[static_cast<size_t>(e)];
                const double du = d + (points.row(u) - points.row(v)).norm();
                if (du < distance[u] && du < blend_width) queue.emplace(distance[u] = du, u);
            }
        }
    }
    std::vector<double> weight(static_cast<size_t>(n), 0.0);
    for (Eigen::Index v = 0; v < n; ++v)
        if (distance[v] < std::numeric_limits<double>::infinity()) weight[v] = blend_profile(distance[v], blend_width);
    return weight;
}

Points blend_by_weight(const Points& points, const Points& changed, const std::vector<double>& weight) {
    if (changed.rows() != points.rows() || changed.cols() != points.cols())
        throw Error("internal: " + std::to_string(changed.rows()) + " changed points for " +
                    std::to_string(points.rows()) + " vertices");
    check_weight(weight, points.rows());
    Points out = points;
    for (Eigen::Index v = 0; v < points.rows(); ++v) out.row(v) = blended(points.row(v), changed.row(v), weight[v]);
    return out;
}

namespace {
Points apply_filter_weighted_unguarded(const Points& points, const Triangles& triangles, const TransferFunction& g,
                                       const std::vector<double>& weight, const FilterOptions& options,
                                       FilterReport* report_out, RegionReport* region_out, FilterCache* cache);
} // namespace

Points apply_filter_weighted(const Points& points, const Triangles& triangles, const TransferFunction& g,
                             const std::vector<double>& weight, const FilterOptions& options, FilterReport* report_out,
                             RegionReport* region_out, FilterCache* cache) {
    try {
        return apply_filter_weighted_unguarded(points, triangles, g, weight, options, report_out, region_out, cache);
    } catch (const std::bad_alloc&) {
        throw Error("out of memory while filtering a region of a mesh of " + std::to_string(points.rows()) +
                    " vertices: select a smaller region, close other programs, or simplify the mesh first");
    }
}

namespace {

Points apply_filter_weighted_unguarded(const Points& points, const Triangles& triangles, const TransferFunction& g,
                                       const std::vector<double>& weight, const FilterOptions& options,
                                       FilterReport* report_out, RegionReport* region_out, FilterCache* cache) {
    const auto t0 = std::chrono::steady_clock::now();
    const Eigen::Index n = points.rows();
    check_weight(weight, n);
    check_faces(triangles, n);
    detail::check_filter_options(g, options);
    // As the whole-mesh filter does, even for vertices the region leaves alone: a result
    // with such a vertex is no valid mesh either.
    check_finite_points(points);

    FilterReport report;
    report.solver = options.solver;
    RegionReport region;
    std::vector<bool> in_domain(static_cast<size_t>(n));
    for (Eigen::Index v = 0; v < n; ++v) in_domain[v] = weight[v] > 0;
    region.domain_vertices = static_cast<int>(std::count(in_domain.begin(), in_domain.end(), true));

    // The sub-mesh: every face touching D. A vertex of D then keeps all its faces, so its
    // rows of K and M are those of the whole mesh, and its open-boundary status too.
    std::vector<int> sub_index(static_cast<size_t>(n), -1);
    std::vector<int> sub_faces;
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        if (in_domain[triangles(f, 0)] || in_domain[triangles(f, 1)] || in_domain[triangles(f, 2)]) {
            sub_faces.push_back(static_cast<int>(f));
            for (int k = 0; k < 3; ++k) sub_index[triangles(f, k)] = 0;
        }
    std::vector<int> sub_vertex;  // ascending, so a sub-mesh of everything is the mesh itself
    for (Eigen::Index v = 0; v < n; ++v)
        if (sub_index[v] == 0) {
            sub_index[v] = static_cast<int>(sub_vertex.size());
            sub_vertex.push_back(static_cast<int>(v));
            if (!in_domain[v]) ++region.ring_vertices;
        }
    region.submesh_vertices = static_cast<int>(sub_vertex.size());

    Points result = points;
    if (sub_faces.empty()) {
        report.warnings.push_back(region.domain_vertices == 0
                                      ? "the region is empty (every weight is 0): nothing changed"
                                      : "no face touches the region: nothing changed");
    } else {
        Points sub_points(static_cast<Eigen::Index>(sub_vertex.size()), 3);
        for (size_t i = 0; i < sub_vertex.size(); ++i) sub_points.row(i) = points.row(sub_vertex[i]);
        Triangles sub_triangles(static_cast<Eigen::Index>(sub_faces.size()), 3);
        for (size_t f = 0; f < sub_faces.size(); ++f)
            for (int k = 0; k < 3; ++k) sub_triangles(f, k) = sub_index[triangles(sub_faces[f], k)];

        // The ring around D is held where it is: the region is the whole-mesh filter on the
        // sub-mesh, with the same checks, solvers and cache.
        std::vector<bool> held(sub_vertex.size());
        for (size_t i = 0; i < sub_vertex.size(); ++i) held[i] = !in_domain[sub_vertex[i]];
        const Points filtered = apply_filter_with_held(sub_points, sub_triangles, held, g, options, &report, cache);
        region.free_components = free_components(sub_triangles, held, options.fix_boundary);
        for (size_t i = 0; i < sub_vertex.size(); ++i) {
            const int v = sub_vertex[i];
            const auto row = static_cast<Eigen::Index>(i);
            // Rows the filter left alone (held, fixed, in no usable face) stay bit for bit.
            if (!in_domain[v] || filtered.row(row) == sub_points.row(row)) continue;
            result.row(v) = blended(points.row(v), filtered.row(row), weight[v]);
        }
        if (!result.allFinite())
            throw Error("the filter produced non-finite coordinates: the transfer function amplifies this mesh too much");
    }
    report.seconds_total = seconds_since(t0);
    detail::report_progress(options, 1.0, "done");
    if (report_out) *report_out = std::move(report);
    if (region_out) *region_out = region;
    return result;
}

} // namespace

} // namespace geofilter
