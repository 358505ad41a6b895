// The exact filter the solvers must reproduce: p' = V G(Lambda) V^-1 p from a dense
// generalized eigen-decomposition K v = lambda M v (paper eq. 3-8). Test-only: O(n^3).
#pragma once

#include "core/operators/laplace.h"
#include "shapes.h"
#include "core/design/transfer_function.h"

#include <algorithm>
#include <cmath>

namespace geofilter::reference {

struct Spectrum {
    Eigen::VectorXd eigenvalues;
    Eigen::MatrixXd eigenvectors;  // M-orthonormal: V^T M V = I, so V^-1 = V^T M
    Eigen::VectorXd mass;
};

// Dense K v = lambda M v with a diagonal M: eigenvalues ascending, eigenvectors M-orthonormal.
// Defined once in spectral.cpp because Eigen's dense eigensolver is the slowest template the
// suites would otherwise instantiate in every test file.
Spectrum dense_spectrum(const Eigen::MatrixXd& stiffness, const Eigen::VectorXd& mass);

// Eigenvalues alone of A v = lambda B v (B symmetric positive definite, not necessarily
// diagonal: a Ritz projection's), ascending.
Eigen::VectorXd generalized_eigenvalues(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

Spectrum spectrum_of(const Mesh& mesh);

// Applies G about the area-weighted centroid, as apply_filter does.
Points spectral_filter(const Spectrum& s, const Points& p, const TransferFunction& g);

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

// RMS over the vertices of the distance between two positions of the same points.
inline double rms_distance(const Points& a, const Points& b) { return std::sqrt((a - b).rowwise().squaredNorm().mean()); }

// The mean over the faces of the angle between a face's normal on `p` and on `truth`, in
// degrees (faces of zero area on either side count as turned by 90).
inline double mean_normal_error_degrees(const Points& p, const Points& truth, const Triangles& triangles) {
    double sum = 0;
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        const auto normal = [&](const Points& q) {
            const Eigen::RowVector3d a = q.row(triangles(f, 0));
            return Eigen::RowVector3d((q.row(triangles(f, 1)) - a).cross(q.row(triangles(f, 2)) - a).normalized());
        };
        sum += std::acos(std::clamp(normal(p).dot(normal(truth)), -1.0, 1.0));
    }
    return triangles.rows() ? sum / static_cast<double>(triangles.rows()) * 180 / M_PI : 0;
}

// Area-weighted RMS of a per-vertex difference: the measure FilterOptions::tolerance bounds.
inline double area_weighted_rms(const Points& difference, const Eigen::VectorXd& mass) {
    return std::sqrt((mass.array() * difference.rowwise().squaredNorm().array()).sum() / mass.sum());
}

} // namespace geofilter::reference
