#include "mesh_prep.h"
#include "solvers.h"

#include <chrono>

namespace geofilter {

const char* solver_name(Solver solver) {
    return solver == Solver::Factored ? "factored (sparse Cholesky)" : "Jacobi-PCG on eq. 9 (paper)";
}

namespace detail {
void report_progress(const FilterOptions& options, double fraction, const std::string& stage) {
    if (options.progress && !options.progress(fraction, stage)) throw Error("cancelled by the user while " + stage);
}
} // namespace detail

Points apply_filter(const Points& points, const Triangles& triangles, const TransferFunction& g,
                    const FilterOptions& options, FilterReport* report_out) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!(options.tolerance > 0 && options.tolerance < 1))
        throw Error("the solver tolerance must lie in (0, 1) (got " + std::to_string(options.tolerance) + ")");
    if (options.max_iterations < 1) throw Error("the iteration cap must be at least 1");
    if (!(options.accuracy > 0)) throw Error("the accuracy must be > 0");
    for (const auto& p : g.poles)
        if (p.imag() == 0 && p.real() >= 0)
            throw Error("unstable filter: a pole lies at s = " + std::to_string(p.real()) + " >= 0");

    FilterReport report;
    report.solver = options.solver;
    const PreparedMesh mesh = prepare_mesh(points, triangles);
    report.warnings = mesh.warnings;
    report.active_vertices = static_cast<int>(mesh.active_vertex.size());

    detail::report_progress(options, 0.0, "assembling the Laplacian");
    const Laplacian laplacian = cotan_laplacian(mesh.points, mesh.triangles);
    // Centre on the area-weighted centroid: translation invariance, and no cancellation for
    // meshes far from the origin.
    const Eigen::RowVector3d centroid = (laplacian.mass.transpose() * mesh.points) / laplacian.mass.sum();
    const Eigen::MatrixXd centred = mesh.points.rowwise() - centroid;
    report.seconds_assembly = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    const double size = (mesh.points.colwise().maxCoeff() - mesh.points.colwise().minCoeff()).norm();
    const detail::FilterProblem problem{laplacian, centred, g, options, size};
    Eigen::MatrixXd filtered = options.solver == Solver::Factored ? detail::solve_factored(problem, report)
                                                                   : detail::solve_jacobi_pcg(problem, report);
    filtered.rowwise() += centroid;
    if (!filtered.allFinite())
        throw Error("the filter produced non-finite coordinates: the mesh is too degenerate for this filter");

    Points result = points;
    for (size_t i = 0; i < mesh.active_vertex.size(); ++i) result.row(mesh.active_vertex[i]) = filtered.row(i);
    report.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    detail::report_progress(options, 1.0, "done");
    if (report_out) *report_out = std::move(report);
    return result;
}

} // namespace geofilter
