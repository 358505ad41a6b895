#include "core/mesh/mesh_prep.h"
#include "core/mesh/seams.h"

#include <algorithm>
#include <cmath>

namespace geofilter {

bool usable_face(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b, const Eigen::RowVector3d& c, long i, long j,
                 long k) {
    const double twice_area = (b - a).cross(c - a).norm();
    const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    // Relative test, so that the verdict does not depend on the unit of length. Below this
    // the cotangents are dominated by rounding error.
    return twice_area > 1e-12 * longest2 && i != j && j != k && i != k;
}

void check_finite_points(const Points& points) {
    for (Eigen::Index i = 0; i < points.rows(); ++i)
        if (!points.row(i).allFinite())
            throw Error("vertex " + std::to_string(i) +
                        " has a NaN or infinite coordinate: remove or repair it (e.g. MeshLab's Remove Unreferenced/Duplicate"
                        " Vertices after deleting it)");
}

PreparedMesh prepare_mesh(const Points& points, const Triangles& triangles) {
    const Eigen::Index n = points.rows();
    if (n == 0) throw Error("the mesh has no vertices");
    if (triangles.rows() == 0)
        throw Error("the mesh has no faces: GeoFilter filters triangle surfaces, not point clouds");
    check_finite_points(points);

    PreparedMesh out;
    std::vector<int> compact(n, -1);
    std::vector<Eigen::Index> kept;
    kept.reserve(triangles.rows());
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        for (int k = 0; k < 3; ++k) {
            const int v = triangles(f, k);
            if (v < 0 || v >= n)
                throw Error("face " + std::to_string(f) + " refers to vertex " + std::to_string(v) + ", but the mesh has only " +
                            std::to_string(n) + " vertices");
        }
        if (!usable_face(points.row(triangles(f, 0)), points.row(triangles(f, 1)), points.row(triangles(f, 2)),
                         triangles(f, 0), triangles(f, 1), triangles(f, 2))) {
            ++out.degenerate_faces;
            continue;
        }
        kept.push_back(f);
        for (int k = 0; k < 3; ++k) compact[triangles(f, k)] = 0;
    }
    if (kept.empty()) throw Error("every face of the mesh has zero area: nothing to filter");

    for (Eigen::Index i = 0; i < n; ++i) {
        if (compact[i] < 0) {
            ++out.isolated_vertices;
            continue;
        }
        compact[i] = static_cast<int>(out.active_vertex.size());
        out.active_vertex.push_back(static_cast<int>(i));
    }
    out.points.resize(static_cast<Eigen::Index>(out.active_vertex.size()), 3);
    for (size_t i = 0; i < out.active_vertex.size(); ++i) out.points.row(i) = points.row(out.active_vertex[i]);
    out.triangles.resize(static_cast<Eigen::Index>(kept.size()), 3);
    for (size_t f = 0; f < kept.size(); ++f)
        for (int k = 0; k < 3; ++k) out.triangles(f, k) = compact[triangles(kept[f], k)];

    // Bit-identical positions on different vertices cut the surface into pieces that the
    // filter then treats separately (an unwelded STL, a split seam): say so.
    const std::vector<int> order = order_by_position(out.points);
    for (size_t i = 1; i < order.size(); ++i)
        if (out.points.row(order[i - 1]) == out.points.row(order[i])) ++out.duplicated_vertices;
    if (out.duplicated_vertices)
        out.warnings.push_back(std::to_string(out.duplicated_vertices) +
                               " vertex/vertices duplicate the position of another: the surface is cut there and each"
                               " side is filtered on its own; weld them first (MeshLab: Cleaning and Repairing > Merge"
                               " Close Vertices)");
    if (out.degenerate_faces)
        out.warnings.push_back(std::to_string(out.degenerate_faces) +
                               " zero-area face(s) skipped: their cotangent weights are undefined");
    if (out.isolated_vertices)
        out.warnings.push_back(std::to_string(out.isolated_vertices) +
                               " vertex/vertices belong to no usable face and were left where they are");
    return out;
}

} // namespace geofilter
