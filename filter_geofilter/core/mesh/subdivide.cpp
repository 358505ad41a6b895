#include "core/mesh/subdivide.h"

#include <map>
#include <utility>
#include <vector>

namespace geofilter {

Mesh subdivide(const Mesh& mesh) {
    const Eigen::Index n = mesh.points.rows(), faces = mesh.triangles.rows();
    std::map<std::pair<int, int>, int> midpoint;
    std::vector<Eigen::RowVector3d> added;
    auto mid = [&](int a, int b) {
        const auto key = std::minmax(a, b);
        const auto [it, inserted] = midpoint.try_emplace(key, static_cast<int>(n + static_cast<Eigen::Index>(added.size())));
        if (inserted) added.push_back(0.5 * (mesh.points.row(a) + mesh.points.row(b)));
        return it->second;
    };
    Mesh out;
    out.triangles.resize(4 * faces, 3);
    for (Eigen::Index t = 0; t < faces; ++t) {
        const int a = mesh.triangles(t, 0), b = mesh.triangles(t, 1), c = mesh.triangles(t, 2);
        const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
        out.triangles.row(4 * t) << a, ab, ca;
        out.triangles.row(4 * t + 1) << b, bc, ab;
        out.triangles.row(4 * t + 2) << c, ca, bc;
        out.triangles.row(4 * t + 3) << ab, bc, ca;
    }
    out.points.resize(n + static_cast<Eigen::Index>(added.size()), 3);
    out.points.topRows(n) = mesh.points;
    for (size_t i = 0; i < added.size(); ++i) out.points.row(n + static_cast<Eigen::Index>(i)) = added[i];
    return out;
}

} // namespace geofilter
