#include "core/feature/feature.h"

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

SelectionMoments selection_moments(const Points& points, const Triangles& triangles, const std::vector<int>& faces,
                                   const Eigen::Vector3d& origin) {
    SelectionMoments m;
    for (int f : faces) {
        if (f < 0 || f >= triangles.rows()) throw Error("selected face index " + std::to_string(f) + " is out of range");
        Eigen::Vector3d v[3];
        for (int k = 0; k < 3; ++k) {
            const int i = triangles(f, k);
            if (i < 0 || i >= points.rows()) throw Error("face " + std::to_string(f) + " refers to a missing vertex");
            v[k] = points.row(i).transpose() - origin;
        }
        const double a = 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).norm();
        if (!std::isfinite(a)) throw Error("a selected face has non-finite coordinates");
        const Eigen::Vector3d sum = v[0] + v[1] + v[2];
        // Integral of x x^T over a triangle: A/12 (sum_i v_i v_i^T + s s^T), s = v0 + v1 + v2.
        m.second += a / 12.0 * (v[0] * v[0].transpose() + v[1] * v[1].transpose() + v[2] * v[2].transpose() +
                                sum * sum.transpose());
        m.first += a / 3.0 * sum;
        m.area += a;
        ++m.face_count;
    }
    return m;
}

FeatureFrame feature_frame(const SelectionMoments& total) {
    if (total.face_count == 0)
        throw Error("no faces are selected: select the feature (a bump, a nose, an ear) before measuring it,"
                    " or turn off useSelection and give s1 directly");
    if (!(total.area > 0))
        throw Error("the selected faces have zero total area: the feature size is undefined; select a larger region");
    FeatureFrame frame;
    frame.mean = total.first / total.area;
    const Eigen::Matrix3d covariance = total.second / total.area - frame.mean * frame.mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance);
    // Eigen sorts ascending; we want the largest spread first.
    for (int k = 0; k < 3; ++k) frame.axes.col(k) = eig.eigenvectors().col(2 - k);
    if (frame.axes.determinant() < 0) frame.axes.col(2) = -frame.axes.col(2);
    return frame;
}

void extend_in_frame(const FeatureFrame& frame, const Eigen::Vector3d& origin, const Points& points,
                     const Triangles& triangles, const std::vector<int>& faces, Eigen::Vector3d& low, Eigen::Vector3d& high) {
    for (int f : faces)
        for (int k = 0; k < 3; ++k) {
            const Eigen::Vector3d local =
                frame.axes.transpose() * ((points.row(triangles(f, k)).transpose() - origin) - frame.mean);
            low = low.cwiseMin(local);
            high = high.cwiseMax(local);
        }
}

FeatureEllipsoid ellipsoid_in_frame(const SelectionMoments& total, const FeatureFrame& frame, const Eigen::Vector3d& origin,
                                    const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
    FeatureEllipsoid e;
    e.axes = frame.axes;
    e.center = origin + (frame.mean + frame.axes * (0.5 * (low + high)));
    e.radii = 0.5 * (high - low);
    e.area = total.area;
    e.face_count = total.face_count;
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

FeatureEllipsoid measure_feature(const Points& points, const Triangles& triangles, const std::vector<int>& selected_faces) {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    if (!selected_faces.empty()) {
        const int f = selected_faces.front();
        if (f < 0 || f >= triangles.rows()) throw Error("selected face index " + std::to_string(f) + " is out of range");
        const int i = triangles(f, 0);
        if (i < 0 || i >= points.rows()) throw Error("face " + std::to_string(f) + " refers to a missing vertex");
        origin = points.row(i).transpose();
    }
    const SelectionMoments moments = selection_moments(points, triangles, selected_faces, origin);
    const FeatureFrame frame = feature_frame(moments);
    Eigen::Vector3d low = Eigen::Vector3d::Constant(INFINITY), high = Eigen::Vector3d::Constant(-INFINITY);
    extend_in_frame(frame, origin, points, triangles, selected_faces, low, high);
    return ellipsoid_in_frame(moments, frame, origin, low, high);
}

FeatureEllipsoid measure_feature_of_points(const Points& points, const std::vector<int>& selected_points,
                                           const Eigen::VectorXd& point_area) {
    if (selected_points.empty())
        throw Error("no points are selected: select the feature's points (a bump, a nose, an ear) before measuring it,"
                    " or turn off useSelection and give the radius");
    if (point_area.size() != points.rows())
        throw Error("internal: " + std::to_string(point_area.size()) + " point areas for " +
                    std::to_string(points.rows()) + " points");
    for (int i : selected_points)
        if (i < 0 || i >= points.rows())
            throw Error("selected point index " + std::to_string(i) + " is out of range (the cloud has " +
                        std::to_string(points.rows()) + " points)");
    // Moments about a selected point, for the reason selection_moments gives.
    const Eigen::Vector3d origin = points.row(selected_points.front()).transpose();
    SelectionMoments moments;
    for (int i : selected_points) {
        const Eigen::Vector3d x = points.row(i).transpose() - origin;
        const double a = point_area[i];
        if (!std::isfinite(a) || !x.allFinite()) throw Error("selected point " + std::to_string(i) + " is not finite");
        moments.area += a;
        moments.first += a * x;
        moments.second += a * x * x.transpose();
    }
    // feature_frame counts selected pieces; here they are points.
    moments.face_count = static_cast<int>(selected_points.size());
    if (!(moments.area > 0))
        throw Error("the selected points stand for zero area: the feature size is undefined; select more points");
    const FeatureFrame frame = feature_frame(moments);
    Eigen::Vector3d low = Eigen::Vector3d::Constant(INFINITY), high = Eigen::Vector3d::Constant(-INFINITY);
    for (int i : selected_points) {
        const Eigen::Vector3d local = frame.axes.transpose() * ((points.row(i).transpose() - origin) - frame.mean);
        low = low.cwiseMin(local);
        high = high.cwiseMax(local);
    }
    FeatureEllipsoid e;
    try {
        e = ellipsoid_in_frame(moments, frame, origin, low, high);
    } catch (const Error&) {
        throw Error("the selected points are degenerate (all on one line): no feature radius; select a patch of points");
    }
    e.face_count = 0;
    e.point_count = static_cast<int>(selected_points.size());
    return e;
}

} // namespace geofilter
