#include "feature.h"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace geofilter {

double feature_radius(const Eigen::Vector3d& radii) {
    const double r1 = radii[0], r2 = radii[1], r3 = radii[2];
    if (!(r2 > 0)) return 0;
    // How far each adjacent pair is from round, on a log scale: 0 for equal radii.
    const double wide_gap = std::log(r1 / r2), narrow_gap = r3 > 0 ? std::log(r2 / r3) : INFINITY;
    // Weight of the wide pair: 1 when the wide pair is round and the narrow one is not (a cap),
    // 0 in the opposite case (a tube), 1/2 when both gaps are equal. Where both gaps vanish
    // (a sphere) every pair has the same mean, so r is continuous there too.
    double wide_weight = 0.5;
    if (std::isinf(narrow_gap)) wide_weight = 1;
    else if (wide_gap + narrow_gap > 0) wide_weight = narrow_gap / (wide_gap + narrow_gap);
    return wide_weight * 0.5 * (r1 + r2) + (1 - wide_weight) * 0.5 * (r2 + r3);
}

FeatureEllipsoid measure_feature(const Points& points, const Triangles& triangles, const std::vector<int>& selected_faces) {
    if (selected_faces.empty())
        throw Error("no faces are selected: select the feature (a bump, a nose, an ear) before measuring it,"
                    " or turn off useSelection and give s1 directly");

    // Moments about a point of the selection, not the origin: on a georeferenced scan
    // (coordinates ~1e6) raw second moments of a 5 cm feature would cancel to rounding noise.
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    bool have_origin = false;
    Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second_moment = Eigen::Matrix3d::Zero();
    double area = 0;
    for (int f : selected_faces) {
        if (f < 0 || f >= triangles.rows()) throw Error("selected face index " + std::to_string(f) + " is out of range");
        Eigen::Vector3d v[3];
        for (int k = 0; k < 3; ++k) {
            const int i = triangles(f, k);
            if (i < 0 || i >= points.rows()) throw Error("face " + std::to_string(f) + " refers to a missing vertex");
            if (!have_origin) {
                origin = points.row(i).transpose();
                have_origin = true;
            }
            v[k] = points.row(i).transpose() - origin;
        }
        const double a = 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).norm();
        if (!std::isfinite(a)) throw Error("a selected face has non-finite coordinates");
        const Eigen::Vector3d sum = v[0] + v[1] + v[2];
        // Integral of x x^T over a triangle: A/12 (sum_i v_i v_i^T + s s^T), s = v0 + v1 + v2.
        second_moment += a / 12.0 * (v[0] * v[0].transpose() + v[1] * v[1].transpose() + v[2] * v[2].transpose() +
                                     sum * sum.transpose());
        first_moment += a / 3.0 * sum;
        area += a;
    }
    if (!(area > 0))
        throw Error("the selected faces have zero total area: the feature size is undefined; select a larger region");

    const Eigen::Vector3d local_mean = first_moment / area;
    const Eigen::Matrix3d covariance = second_moment / area - local_mean * local_mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance);
    // Eigen sorts ascending; we want the largest spread first.
    Eigen::Matrix3d axes;
    for (int k = 0; k < 3; ++k) axes.col(k) = eig.eigenvectors().col(2 - k);
    if (axes.determinant() < 0) axes.col(2) = -axes.col(2);

    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
    for (int f : selected_faces)
        for (int k = 0; k < 3; ++k) {
            const Eigen::Vector3d local =
                axes.transpose() * ((points.row(triangles(f, k)).transpose() - origin) - local_mean);
            lo = lo.cwiseMin(local);
            hi = hi.cwiseMax(local);
        }

    FeatureEllipsoid e;
    e.axes = axes;
    e.center = origin + (local_mean + axes * (0.5 * (lo + hi)));
    e.radii = 0.5 * (hi - lo);
    e.area = area;
    e.face_count = static_cast<int>(selected_faces.size());
    // PCA can order two nearly equal spreads either way; the box extents decide the order.
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2 - i; ++j)
            if (e.radii[j] < e.radii[j + 1]) {
                std::swap(e.radii[j], e.radii[j + 1]);
                e.axes.col(j).swap(e.axes.col(j + 1));
            }
    e.radius = feature_radius(e.radii);
    if (!(e.radius > 0)) throw Error("the selected faces are degenerate (all on one line): no feature radius");
    return e;
}

} // namespace geofilter
