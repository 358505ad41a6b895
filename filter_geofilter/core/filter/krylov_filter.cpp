#include "core/filter/krylov_filter.h"

#include "core/mesh/mesh_prep.h"
#include "core/mesh/surface_measures.h"

#include <cmath>

namespace geofilter {

std::optional<Points> krylov_filter(const Points& points, const Triangles& triangles, const TransferFunction& g, Operator op,
                                    double tolerance, int max_steps, KrylovReport* report) {
    const PreparedMesh mesh = prepare_mesh(points, triangles);
    const Laplacian l = build_laplacian(op, mesh.points, mesh.triangles);
    KrylovReport r;
    const double allowed = tolerance * bounding_box_diagonal(mesh.points) * std::sqrt(l.mass.sum());
    const Eigen::MatrixXd filtered = krylov_lowpass(l, mesh.points, g, allowed, max_steps, &r);
    if (report) *report = r;
    if (!r.converged) return std::nullopt;
    Points out = points;
    for (Eigen::Index i = 0; i < filtered.rows(); ++i) out.row(mesh.active_vertex[static_cast<std::size_t>(i)]) = filtered.row(i);
    return out;
}

} // namespace geofilter
