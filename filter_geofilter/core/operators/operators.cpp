#include "core/operators/operators.h"

#include "core/operators/intrinsic_delaunay.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace geofilter {

bool operator_uses_positions(Operator op) { return op != Operator::Umbrella; }

const char* operator_name(Operator op) {
    switch (op) {
    case Operator::Cotangent: return "cotangent";
    case Operator::IntrinsicDelaunay: return "intrinsic Delaunay cotangent";
    case Operator::Umbrella: return "umbrella (graph, per-vertex frequency)";
    }
    return "?";
}

Laplacian umbrella_laplacian(const Triangles& triangles, Eigen::Index vertex_count) {
    std::vector<std::pair<int, int>> edges;
    edges.reserve(static_cast<size_t>(triangles.rows()) * 3);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        for (int i = 0; i < 3; ++i) {
            const int a = triangles(f, i), b = triangles(f, (i + 1) % 3);
            edges.emplace_back(std::min(a, b), std::max(a, b));
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    Laplacian result;
    result.mass = Eigen::VectorXd::Zero(vertex_count);
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(edges.size() * 4);
    for (const auto& [a, b] : edges) {
        entries.emplace_back(a, b, -1.0);
        entries.emplace_back(b, a, -1.0);
        entries.emplace_back(a, a, 1.0);
        entries.emplace_back(b, b, 1.0);
        result.mass[a] += 1;
        result.mass[b] += 1;
    }
    result.stiffness.resize(vertex_count, vertex_count);
    result.stiffness.setFromTriplets(entries.begin(), entries.end());
    return result;
}

Laplacian build_laplacian(Operator op, const Points& points, const Triangles& triangles) {
    switch (op) {
    case Operator::IntrinsicDelaunay: return intrinsic_delaunay_laplacian(points, triangles);
    case Operator::Umbrella: return umbrella_laplacian(triangles, points.rows());
    case Operator::Cotangent: break;
    }
    return cotan_laplacian(points, triangles);
}

} // namespace geofilter
