#include "icosphere.h"

#include <map>
#include <utility>
#include <vector>

namespace geofilter {

Mesh mesh_from_lists(const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& f) {
    Mesh m;
    m.points.resize(static_cast<Eigen::Index>(v.size()), 3);
    for (size_t i = 0; i < v.size(); ++i) m.points.row(i) = v[i].transpose();
    m.triangles.resize(static_cast<Eigen::Index>(f.size()), 3);
    for (size_t i = 0; i < f.size(); ++i) m.triangles.row(i) = f[i].transpose();
    return m;
}

Mesh subdivide(const Mesh& mesh) {
    std::vector<Eigen::Vector3d> v;
    v.reserve(mesh.points.rows() * 4);
    for (Eigen::Index i = 0; i < mesh.points.rows(); ++i) v.emplace_back(mesh.points.row(i).transpose());
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
        const auto key = std::minmax(a, b);
        auto it = midpoint.find(key);
        if (it != midpoint.end()) return it->second;
        v.push_back(0.5 * (v[a] + v[b]));
        return midpoint[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Eigen::Vector3i> f;
    f.reserve(mesh.triangles.rows() * 4);
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
        const int a = mesh.triangles(t, 0), b = mesh.triangles(t, 1), c = mesh.triangles(t, 2);
        const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
        f.emplace_back(a, ab, ca);
        f.emplace_back(b, bc, ab);
        f.emplace_back(c, ca, bc);
        f.emplace_back(ab, bc, ca);
    }
    return mesh_from_lists(v, f);
}

Mesh subdivide_onto_sphere(Mesh mesh, int levels, double radius) {
    for (int l = 0; l < levels; ++l) mesh = subdivide(mesh);
    for (Eigen::Index i = 0; i < mesh.points.rows(); ++i) mesh.points.row(i) = radius * mesh.points.row(i).normalized();
    return mesh;
}

Mesh icosphere(int levels, double radius) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    const std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    const std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                            {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                            {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    return subdivide_onto_sphere(mesh_from_lists(v, f), levels, radius);
}

} // namespace geofilter
