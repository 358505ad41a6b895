#include "laplace.h"

#include <vector>

namespace geofilter {

Laplacian cotan_laplacian(const Points& points, const Triangles& triangles,
                          const std::vector<bool>& skip_face) {
    const Eigen::Index n = points.rows();
    Laplacian result;
    result.mass = Eigen::VectorXd::Zero(n);

    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<size_t>(triangles.rows()) * 9);

    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        if (!skip_face.empty() && skip_face[f]) continue;
        const int idx[3] = {triangles(f, 0), triangles(f, 1), triangles(f, 2)};
        const Eigen::Vector3d p[3] = {points.row(idx[0]).transpose(), points.row(idx[1]).transpose(),
                                      points.row(idx[2]).transpose()};
        const double twice_area = (p[1] - p[0]).cross(p[2] - p[0]).norm();
        for (int corner = 0; corner < 3; ++corner) {
            // The angle at `corner` faces the edge (a, b); its cotangent couples a and b.
            const int a = (corner + 1) % 3, b = (corner + 2) % 3;
            const Eigen::Vector3d u = p[a] - p[corner], v = p[b] - p[corner];
            // cot = cos/sin = (u.v) / |u x v|; |u x v| is twice the area for every corner.
            const double half_cot = 0.5 * u.dot(v) / twice_area;
            entries.emplace_back(idx[a], idx[b], -half_cot);
            entries.emplace_back(idx[b], idx[a], -half_cot);
            entries.emplace_back(idx[a], idx[a], half_cot);
            entries.emplace_back(idx[b], idx[b], half_cot);
            result.mass[idx[corner]] += twice_area / 6.0;
        }
    }
    result.stiffness.resize(n, n);
    result.stiffness.setFromTriplets(entries.begin(), entries.end());
    return result;
}

SparseMatrix mass_normalized_stiffness(const Laplacian& laplacian) {
    const Eigen::VectorXd inv_sqrt = laplacian.mass.cwiseSqrt().cwiseInverse();
    SparseMatrix kt = laplacian.stiffness;
    for (Eigen::Index col = 0; col < kt.outerSize(); ++col)
        for (SparseMatrix::InnerIterator it(kt, col); it; ++it) it.valueRef() *= inv_sqrt[it.row()] * inv_sqrt[col];
    return kt;
}

} // namespace geofilter
