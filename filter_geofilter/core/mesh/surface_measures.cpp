#include "core/mesh/surface_measures.h"

namespace geofilter {

Eigen::MatrixXd vertex_normals(const Points& points, const Triangles& triangles) {
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(points.rows(), 3);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        const Eigen::RowVector3d weighted = twice_area_normal(points, triangles, f).transpose();
        for (int k = 0; k < 3; ++k) normal.row(triangles(f, k)) += weighted;
    }
    for (Eigen::Index v = 0; v < normal.rows(); ++v) {
        const double length = normal.row(v).norm();
        if (length > 0) normal.row(v) /= length;
    }
    return normal;
}

Eigen::VectorXd vertex_areas(const Points& points, const Triangles& triangles) {
    Eigen::VectorXd area = Eigen::VectorXd::Zero(points.rows());
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        const double third_of_area = twice_area_normal(points, triangles, f).norm() / 6;
        for (int k = 0; k < 3; ++k) area[triangles(f, k)] += third_of_area;
    }
    return area;
}

double mean_edge_length(const Points& points, const Triangles& triangles) {
    double sum = 0;
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        for (int i = 0; i < 3; ++i) sum += (points.row(triangles(f, i)) - points.row(triangles(f, (i + 1) % 3))).norm();
    return triangles.rows() > 0 ? sum / (3.0 * static_cast<double>(triangles.rows())) : 0.0;
}

} // namespace geofilter
