// The exact filter the solvers must reproduce: p' = V G(Lambda) V^-1 p from a dense
// generalized eigen-decomposition K v = lambda M v (paper eq. 3-8). Test-only: O(n^3).
#pragma once

#include "core/operators/laplace.h"
#include "shapes.h"
#include "core/design/transfer_function.h"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace geofilter::reference {

struct Spectrum {
    Eigen::VectorXd eigenvalues;
    Eigen::MatrixXd eigenvectors;  // M-orthonormal: V^T M V = I, so V^-1 = V^T M
    Eigen::VectorXd mass;
};

inline Spectrum spectrum_of(const Mesh& mesh) {
    const Laplacian l = cotan_laplacian(mesh.points, mesh.triangles);
    const Eigen::MatrixXd k = Eigen::MatrixXd(l.stiffness);
    const Eigen::MatrixXd m = l.mass.asDiagonal();
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k, m);
    return {eig.eigenvalues(), eig.eigenvectors(), l.mass};
}

// Applies G about the area-weighted centroid, as apply_filter does.
inline Points spectral_filter(const Spectrum& s, const Points& p, const TransferFunction& g) {
    const Eigen::RowVector3d c = (s.mass.transpose() * p) / s.mass.sum();
    const Eigen::MatrixXd centred = p.rowwise() - c;
    Eigen::VectorXd gains(s.eigenvalues.size());
    for (Eigen::Index i = 0; i < gains.size(); ++i) gains[i] = g(std::max(0.0, s.eigenvalues[i]));
    const Eigen::MatrixXd modal = s.eigenvectors.transpose() * (s.mass.asDiagonal() * centred);
    Eigen::MatrixXd out = s.eigenvectors * (gains.asDiagonal() * modal);
    out.rowwise() += c;
    return out;
}

// A square sheet with waves of several frequencies and a saddle: open boundary, curved, no
// symmetry a filter could hide behind.
inline Mesh wavy_sheet(int n) {
    Mesh g = grid(n, 1.0);
    for (Eigen::Index i = 0; i < g.points.rows(); ++i) {
        const double x = g.points(i, 0), y = g.points(i, 1);
        g.points(i, 2) = 0.05 * std::sin(9 * x) * std::cos(7 * y) + 0.1 * x * y;
    }
    return g;
}

inline double bbox_diagonal(const Points& p) { return (p.colwise().maxCoeff() - p.colwise().minCoeff()).norm(); }

inline double mean_radius(const Points& p, const Eigen::RowVector3d& centre = Eigen::RowVector3d::Zero()) {
    return (p.rowwise() - centre).rowwise().norm().mean();
}

// Area-weighted RMS of a per-vertex difference: the measure FilterOptions::tolerance bounds.
inline double area_weighted_rms(const Points& difference, const Eigen::VectorXd& mass) {
    return std::sqrt((mass.array() * difference.rowwise().squaredNorm().array()).sum() / mass.sum());
}

} // namespace geofilter::reference
