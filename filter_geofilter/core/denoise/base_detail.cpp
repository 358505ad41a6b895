#include "core/denoise/base_detail.h"
#include "core/mesh/boundary.h"
#include "core/mesh/surface_measures.h"

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <cmath>

namespace geofilter {

Eigen::VectorXd base_detail(const Eigen::VectorXd& removed, const Laplacian& laplacian, double radius,
                            const std::vector<int>& selected, BaseDetailReport* report) {
    const Eigen::Index n = removed.size();
    if (laplacian.mass.size() != n || laplacian.stiffness.rows() != n)
        throw Error("base_detail: the Laplacian is not of the removed heights' mesh");
    if (!(radius > 0) || !std::isfinite(radius)) throw Error("base_detail: the bump radius must be positive");
    const Eigen::VectorXd& mass = laplacian.mass;
    // Vertices of zero mass have no data and no penalty: a unit diagonal keeps them at 0.
    Eigen::VectorXd inverse_mass(n), zero_mass_unit = Eigen::VectorXd::Zero(n);
    for (Eigen::Index v = 0; v < n; ++v) {
        inverse_mass[v] = mass[v] > 0 ? 1 / mass[v] : 0;
        if (!(mass[v] > 0)) zero_mass_unit[v] = 1;
    }
    const double lambda = radius * radius / 2;
    SparseMatrix penalty = lambda * lambda * (laplacian.stiffness * inverse_mass.asDiagonal() * laplacian.stiffness);
    penalty.makeCompressed();
    Eigen::VectorXd weight = Eigen::VectorXd::Ones(n);
    Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> factor;
    Eigen::VectorXd field = Eigen::VectorXd::Zero(n);
    BaseDetailReport r;
    double threshold = -1;
    for (r.rounds = 1; r.rounds <= base_detail_max_rounds; ++r.rounds) {
        const Eigen::VectorXd weighted_mass = weight.cwiseProduct(mass);
        SparseMatrix system = penalty;
        system += SparseMatrix((weighted_mass + zero_mass_unit).asDiagonal());
        if (r.rounds == 1) factor.analyzePattern(system);
        factor.factorize(system);
        if (factor.info() != Eigen::Success) throw Error("base_detail: the penalised fit could not be factored");
        field = factor.solve(weighted_mass.cwiseProduct(removed));
        if (threshold < 0) {
            for (int v : selected)
                if (v >= 0 && v < n) r.selected_height = std::max(r.selected_height, std::abs(removed[v] - field[v]));
            threshold = base_detail_bump_share * r.selected_height;
            if (!(threshold > 0)) break;  // nothing stands out at the selection: the plain fit
        }
        Eigen::Index changed = 0;
        for (Eigen::Index v = 0; v < n; ++v) {
            const double w = std::abs(removed[v] - field[v]) > threshold ? base_detail_bump_weight : 1.0;
            if (w != weight[v]) ++changed;
            weight[v] = w;
        }
        if (static_cast<double>(changed) < base_detail_settled * static_cast<double>(n)) break;
    }
    r.rounds = std::min(r.rounds, base_detail_max_rounds);
    double total = mass.sum(), down = 0;
    for (Eigen::Index v = 0; v < n; ++v)
        if (weight[v] < 1) down += mass[v];
    r.bump_area_share = total > 0 ? down / total : 0;
    if (report) *report = r;
    return field;
}

Points with_base_detail(const Points& input, const Points& lowpassed, const Triangles& triangles,
                        const std::vector<int>& bump_faces, double radius, BaseDetailReport* report) {
    const Eigen::MatrixXd normal = vertex_normals(lowpassed, triangles);
    Eigen::VectorXd removed(input.rows());
    for (Eigen::Index v = 0; v < input.rows(); ++v) removed[v] = (input.row(v) - lowpassed.row(v)).dot(normal.row(v));
    std::vector<int> selected;
    for (int f : bump_faces)
        if (f >= 0 && f < triangles.rows())
            for (int k = 0; k < 3; ++k) selected.push_back(triangles(f, k));
    const Eigen::VectorXd base = base_detail(removed, cotan_laplacian(lowpassed, triangles), radius, selected, report);
    const std::vector<bool> rim = boundary_vertices(triangles, input.rows());
    Points out = lowpassed;
    for (Eigen::Index v = 0; v < out.rows(); ++v)
        if (!rim[static_cast<std::size_t>(v)]) out.row(v) += base[v] * normal.row(v);
    return out;
}

} // namespace geofilter
