#include "core/denoise/noise_direction.h"
#include "core/operators/operators.h"
#include "core/mesh/surface_measures.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <vector>

namespace geofilter {

const char* noise_model_name(NoiseModel model) {
    switch (model) {
    case NoiseModel::Isotropic: return "in every direction";
    case NoiseModel::AlongDirection: return "along one direction";
    case NoiseModel::AlongNormals: break;
    }
    return "along the normals";
}

namespace {

constexpr double isotropic_ratio = 2.0;
constexpr double regular_quantile = 0.05;
constexpr int normal_smoothing_rings = 3;  // the normals' own noise stays out of the split
constexpr int averaging_rings = 4;

double quantile(std::vector<double> values, double q) {
    const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
    std::nth_element(values.begin(), values.begin() + k, values.end());
    return values[static_cast<std::size_t>(k)];
}

} // namespace

Eigen::MatrixXd smoothed_vertex_normals(const Points& points, const Triangles& triangles) {
    const Laplacian umbrella = umbrella_laplacian(triangles, points.rows());
    Eigen::MatrixXd normal = vertex_normals(points, triangles);
    for (int ring = 0; ring < normal_smoothing_rings; ++ring) {
        normal += umbrella.mass.asDiagonal() * normal - umbrella.stiffness * normal;  // + the neighbours' sum
        for (Eigen::Index i = 0; i < normal.rows(); ++i)
            if (const double length = normal.row(i).norm(); length > 0) normal.row(i) /= length;
    }
    return normal;
}

NoiseDirection estimate_noise_direction(const Points& points, const Triangles& triangles, const Eigen::VectorXd* variance) {
    const Laplacian umbrella = umbrella_laplacian(triangles, points.rows());
    const Eigen::VectorXd& degree = umbrella.mass;
    const SparseMatrix& k = umbrella.stiffness;
    // Neighbour sums: A x = D x - K x.
    const auto neighbour_sum = [&](const Eigen::MatrixXd& x) -> Eigen::MatrixXd {
        return degree.asDiagonal() * x - k * x;
    };

    const Eigen::MatrixXd normal = smoothed_vertex_normals(points, triangles);
    // The umbrella offset of the umbrella offsets: the clean surface's part of an offset (its
    // curvature along the normal, long edges' more) changes slowly from vertex to vertex and
    // mostly cancels, while independent noise still adds the same to each axis, so the pure
    // noise's ratio stays 2. With the offsets themselves, noise in random directions on a
    // torus sampled 4x longer one way read 1.93, below noise along the normals' largest.
    const auto umbrella_offset = [&](const Eigen::MatrixXd& x) -> Eigen::MatrixXd {
        return -(degree.cwiseMax(1.0).cwiseInverse().asDiagonal() * (k * x));
    };
    const Eigen::MatrixXd offset = umbrella_offset(umbrella_offset(points));
    Eigen::MatrixXd parts(points.rows(), 2);  // squared normal and tangential parts
    std::vector<bool> used(points.rows());
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
        used[i] = degree[i] > 0 && normal.row(i).squaredNorm() > 0;
        const double along = used[i] ? offset.row(i).dot(normal.row(i)) : 0.0;
        parts(i, 0) = along * along;
        parts(i, 1) = used[i] ? offset.row(i).squaredNorm() - along * along : 0.0;
    }
    for (int ring = 0; ring < averaging_rings; ++ring)
        parts = (parts + neighbour_sum(parts)).cwiseQuotient((degree.array() + 1.0).matrix().replicate(1, 2));

    // The ratio of the parts' low quantiles over the vertices in `where`.
    const auto tangential_ratio = [&](const std::vector<bool>& where) {
        std::vector<double> along, across;
        for (Eigen::Index i = 0; i < points.rows(); ++i)
            if (where[i]) {
                along.push_back(parts(i, 0));
                across.push_back(parts(i, 1));
            }
        if (along.empty()) return 0.0;
        const double normal_part = quantile(along, regular_quantile);
        return normal_part > 0 ? quantile(across, regular_quantile) / normal_part : 0.0;
    };
    NoiseDirection out;
    out.tangential_ratio = tangential_ratio(used);
    if (!(out.tangential_ratio > 0)) return out;  // no noise along the normals to compare with
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (Eigen::Index i = 0; i < points.rows(); ++i)
        if (used[i]) covariance += offset.row(i).transpose() * offset.row(i);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> principal(covariance);
    if (principal.info() == Eigen::Success && principal.eigenvalues().sum() > 0) {
        out.direction = principal.eigenvectors().col(2);
        out.direction_share = principal.eigenvalues()[2] / principal.eigenvalues().sum();
    }
    double ratio = out.tangential_ratio;
    const bool along_one_direction = ratio >= isotropic_ratio && out.direction_share >= noise_direction_share;
    if (!along_one_direction && variance) {
        double sum = 0;
        int count = 0;
        for (Eigen::Index i = 0; i < points.rows(); ++i)
            if (used[i]) sum += (*variance)[i], ++count;
        std::vector<bool> noisy(used);
        for (Eigen::Index i = 0; i < points.rows(); ++i)
            noisy[i] = used[i] && (*variance)[i] >= noisy_vertex_share * sum / count;
        out.tangential_ratio_where_noisy = tangential_ratio(noisy);
        if (out.tangential_ratio_where_noisy > 0) ratio = out.tangential_ratio_where_noisy;
    }
    out.model = ratio < isotropic_ratio                                ? NoiseModel::AlongNormals
                : out.direction_share >= noise_direction_share ? NoiseModel::AlongDirection
                                                                : NoiseModel::Isotropic;
    return out;
}

} // namespace geofilter
