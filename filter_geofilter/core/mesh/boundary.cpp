#include "core/mesh/boundary.h"
#include "core/mesh/components.h"

#include <Eigen/CholmodSupport>

#include <algorithm>
#include <utility>

namespace geofilter {

std::vector<bool> boundary_vertices(const Triangles& triangles, Eigen::Index vertex_count) {
    std::vector<std::pair<int, int>> edges;
    edges.reserve(static_cast<size_t>(triangles.rows()) * 3);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        for (int k = 0; k < 3; ++k) edges.push_back(std::minmax(triangles(f, k), triangles(f, (k + 1) % 3)));
    std::sort(edges.begin(), edges.end());
    std::vector<bool> on_boundary(static_cast<size_t>(vertex_count), false);
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        if (j - i == 1) on_boundary[edges[i].first] = on_boundary[edges[i].second] = true;
        i = j;
    }
    return on_boundary;
}

namespace {

std::vector<int> compact_index(const std::vector<bool>& keep) {
    std::vector<int> index(keep.size(), -1);
    int next = 0;
    for (size_t i = 0; i < keep.size(); ++i)
        if (keep[i]) index[i] = next++;
    return index;
}

} // namespace

Laplacian restrict_laplacian(const Laplacian& laplacian, const std::vector<bool>& keep) {
    const std::vector<int> index = compact_index(keep);
    const Eigen::Index kept = std::count(keep.begin(), keep.end(), true);
    std::vector<Eigen::Triplet<double>> entries;
    for (Eigen::Index col = 0; col < laplacian.stiffness.outerSize(); ++col) {
        if (!keep[col]) continue;
        for (SparseMatrix::InnerIterator it(laplacian.stiffness, col); it; ++it)
            if (keep[it.row()]) entries.emplace_back(index[it.row()], index[col], it.value());
    }
    Laplacian out;
    out.stiffness.resize(kept, kept);
    out.stiffness.setFromTriplets(entries.begin(), entries.end());
    out.mass.resize(kept);
    for (size_t i = 0; i < keep.size(); ++i)
        if (keep[i]) out.mass[index[i]] = laplacian.mass[static_cast<Eigen::Index>(i)];
    return out;
}

Eigen::MatrixXd harmonic_extension(const Laplacian& laplacian, const std::vector<bool>& on_boundary,
                                   const Eigen::MatrixXd& points) {
    // Only components that touch the boundary have a harmonic extension; a closed component
    // gets h = 0. Leaving closed components out of the solve (instead of regularising K_II
    // with a shift) keeps h exactly harmonic: a shift scaled by the stiffest vertex becomes
    // large on a mesh with one sliver and turns h into a screened extension.
    const std::vector<int> component = connected_components(laplacian.stiffness);
    std::vector<bool> bounded(static_cast<size_t>(component_count(component)), false);
    for (size_t i = 0; i < on_boundary.size(); ++i)
        if (on_boundary[i]) bounded[component[i]] = true;
    std::vector<bool> unknown(on_boundary.size());
    for (size_t i = 0; i < unknown.size(); ++i) unknown[i] = !on_boundary[i] && bounded[component[i]];
    const std::vector<int> index = compact_index(unknown);
    const Laplacian inner = restrict_laplacian(laplacian, unknown);

    Eigen::MatrixXd h = points;
    for (size_t i = 0; i < unknown.size(); ++i)
        if (!on_boundary[i] && !unknown[i]) h.row(static_cast<Eigen::Index>(i)).setZero();
    if (inner.mass.size() == 0) return h;

    // Right-hand side -K_IB p_B, one column per column of `points` (coordinates, or a field's).
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(inner.mass.size(), points.cols());
    for (Eigen::Index col = 0; col < laplacian.stiffness.outerSize(); ++col) {
        if (!on_boundary[col]) continue;
        for (SparseMatrix::InnerIterator it(laplacian.stiffness, col); it; ++it)
            if (unknown[it.row()]) rhs.row(index[it.row()]) -= it.value() * points.row(col);
    }
    Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt(inner.stiffness);
    if (llt.info() != Eigen::Success)
        throw Error("the fixed-boundary system could not be factorised: the mesh has inverted or degenerate faces");
    const Eigen::MatrixXd h_inner = llt.solve(rhs);
    for (size_t i = 0; i < unknown.size(); ++i)
        if (unknown[i]) h.row(static_cast<Eigen::Index>(i)) = h_inner.row(index[i]);
    return h;
}

} // namespace geofilter
