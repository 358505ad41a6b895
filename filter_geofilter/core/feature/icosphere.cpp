#include "core/feature/icosphere.h"

#include "core/mesh/subdivide.h"

#include <cmath>

namespace geofilter {

Mesh icosphere(int levels, double radius) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    Mesh mesh;
    mesh.points.resize(12, 3);
    mesh.points << -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1,
        -t, 0, -1, -t, 0, 1;
    mesh.triangles.resize(20, 3);
    mesh.triangles << 0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
        3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1;
    for (int l = 0; l < levels; ++l) mesh = subdivide(mesh);
    mesh.points.rowwise().normalize();
    mesh.points *= radius;
    return mesh;
}

} // namespace geofilter
