#include "shapes.h"
#include "core/mesh/surface_measures.h"

#include <cmath>
#include <random>
#include <vector>

namespace geofilter {

Mesh mesh_from_lists(const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& f) {
    Mesh m;
    m.points.resize(static_cast<Eigen::Index>(v.size()), 3);
    for (size_t i = 0; i < v.size(); ++i) m.points.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
    m.triangles.resize(static_cast<Eigen::Index>(f.size()), 3);
    for (size_t i = 0; i < f.size(); ++i) m.triangles.row(static_cast<Eigen::Index>(i)) = f[i].transpose();
    return m;
}

Mesh subdivide_onto_sphere(Mesh mesh, int levels, double radius) {
    for (int l = 0; l < levels; ++l) mesh = subdivide(mesh);
    mesh.points.rowwise().normalize();
    mesh.points *= radius;
    return mesh;
}

Mesh tetrasphere(int levels, double radius) {
    const std::vector<Eigen::Vector3d> v = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    const std::vector<Eigen::Vector3i> f = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    return subdivide_onto_sphere(mesh_from_lists(v, f), levels, radius);
}

Mesh uv_sphere(int rings, int segments, double radius) {
    std::vector<Eigen::Vector3d> v = {{0, 0, radius}};
    for (int i = 1; i < rings; ++i) {
        const double theta = M_PI * i / rings;
        for (int j = 0; j < segments; ++j) {
            const double phi = 2 * M_PI * j / segments;
            v.emplace_back(radius * std::sin(theta) * std::cos(phi), radius * std::sin(theta) * std::sin(phi),
                           radius * std::cos(theta));
        }
    }
    v.emplace_back(0, 0, -radius);
    const int south = static_cast<int>(v.size()) - 1;
    auto at = [&](int ring, int seg) { return 1 + (ring - 1) * segments + (seg % segments); };
    std::vector<Eigen::Vector3i> f;
    for (int j = 0; j < segments; ++j) {
        f.emplace_back(0, at(1, j), at(1, j + 1));
        f.emplace_back(south, at(rings - 1, j + 1), at(rings - 1, j));
    }
    for (int i = 1; i < rings - 1; ++i)
        for (int j = 0; j < segments; ++j) {
            f.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            f.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    return mesh_from_lists(v, f);
}

Mesh cylinder(int rings, int segments, double radius, double length) {
    std::vector<Eigen::Vector3d> v;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j < segments; ++j) {
            // Alternate rings are rotated by half a segment: nearly equilateral triangles.
            const double phi = 2 * M_PI * (j + 0.5 * (i % 2)) / segments;
            v.emplace_back(radius * std::cos(phi), radius * std::sin(phi), -0.5 * length + length * i / rings);
        }
    std::vector<Eigen::Vector3i> f;
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const int a = i * segments + j, b = i * segments + (j + 1) % segments;
            const int c = (i + 1) * segments + j, d = (i + 1) * segments + (j + 1) % segments;
            if (i % 2 == 0) {
                f.emplace_back(a, b, c);
                f.emplace_back(b, d, c);
            } else {
                f.emplace_back(a, d, c);
                f.emplace_back(a, b, d);
            }
        }
    return mesh_from_lists(v, f);
}

Mesh torus(int rings, int segments, double major_radius, double minor_radius) {
    std::vector<Eigen::Vector3d> v;
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const double u = 2 * M_PI * i / rings, w = 2 * M_PI * j / segments;
            const double rr = major_radius + minor_radius * std::cos(w);
            v.emplace_back(rr * std::cos(u), rr * std::sin(u), minor_radius * std::sin(w));
        }
    std::vector<Eigen::Vector3i> f;
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const int a = i * segments + j, b = i * segments + (j + 1) % segments;
            const int c = ((i + 1) % rings) * segments + j, d = ((i + 1) % rings) * segments + (j + 1) % segments;
            f.emplace_back(a, c, d);
            f.emplace_back(a, d, b);
        }
    return mesh_from_lists(v, f);
}

Mesh grid(int n, double size) {
    std::vector<Eigen::Vector3d> v;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) v.emplace_back(size * (double(j) / n - 0.5), size * (double(i) / n - 0.5), 0);
    std::vector<Eigen::Vector3i> f;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const int a = i * (n + 1) + j, b = a + 1, c = a + n + 1, d = c + 1;
            f.emplace_back(a, b, d);
            f.emplace_back(a, d, c);
        }
    return mesh_from_lists(v, f);
}

void perturb_radially(Mesh& mesh, double amplitude, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (Eigen::Index i = 0; i < mesh.points.rows(); ++i) {
        const Eigen::RowVector3d p = mesh.points.row(i);
        const double n = p.norm();
        if (n > 0) mesh.points.row(i) = p + amplitude * unit(rng) * p / n;
    }
}

Points noised_along_normals(const Mesh& mesh, double sigma, unsigned seed) {
    const Eigen::MatrixXd normal = vertex_normals(mesh.points, mesh.triangles);
    std::mt19937 random(seed);
    std::normal_distribution<double> gauss(0.0, sigma);
    Points out = mesh.points;
    for (Eigen::Index i = 0; i < out.rows(); ++i) out.row(i) += gauss(random) * normal.row(i);
    return out;
}

Points fibonacci_sphere(int count, double radius) {
    Points p(count, 3);
    const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / count, ring = std::sqrt(1.0 - z * z);
        p.row(i) = radius * Eigen::RowVector3d(ring * std::cos(golden_angle * i), ring * std::sin(golden_angle * i), z);
    }
    return p;
}

} // namespace geofilter
