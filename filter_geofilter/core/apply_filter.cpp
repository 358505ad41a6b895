#include "boundary.h"
#include "pcg.h"
#include "components.h"
#include "mesh_prep.h"
#include "solvers.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <new>

namespace geofilter {

namespace {
Points apply_filter_unguarded(const Points& points, const Triangles& triangles, const TransferFunction& g,
                              const FilterOptions& options, FilterReport* report_out);
} // namespace

const char* solver_name(Solver solver) {
    return solver == Solver::Factored ? "factored (sparse Cholesky)" : "Jacobi-PCG on eq. 9 (paper)";
}

double estimated_filter_bytes(Eigen::Index vertices) { return 1500.0 * static_cast<double>(vertices); }

namespace {

double available_memory_bytes() {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    double kib = 0;
    std::string unit;
    while (meminfo >> key >> kib >> unit)
        if (key == "MemAvailable:") return kib * 1024.0;
    return 0;  // unknown: no up-front check
}

std::string gib(double bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f GiB", bytes / (1024.0 * 1024.0 * 1024.0));
    return text;
}

} // namespace

namespace detail {
Eigen::MatrixXd apply_polynomial(const SparseMatrix& kt, const std::vector<double>& c, const Eigen::MatrixXd& y) {
    Eigen::MatrixXd acc = c.back() * y;
    for (int k = static_cast<int>(c.size()) - 2; k >= 0; --k) {
        Eigen::MatrixXd next = kt * acc;
        next += c[k] * y;
        acc.swap(next);
    }
    return acc;
}

double allowed_error(const FilterProblem& problem) {
    return problem.options.tolerance * problem.size * std::sqrt(problem.laplacian.mass.sum());
}

void record_pcg_outcome(const PcgOutcome& outcome, double allowed_error, const std::string& advice, FilterReport& report) {
    report.iterations += outcome.iterations;
    report.relative_residual = std::max(report.relative_residual, outcome.relative_residual);
    if (outcome.cancelled) throw Error("cancelled by the user");
    if (!outcome.converged)
        throw Error("the solver did not converge in " + std::to_string(outcome.iterations) + " iterations (its error bound is " +
                    format_number(outcome.error_bound / allowed_error) + " times what the tolerance allows); " + advice);
}

void check_filter_options(const TransferFunction& g, const FilterOptions& options) {
    if (!(options.tolerance > 0 && options.tolerance < 1))
        throw Error("the solver tolerance must lie in (0, 1) (got " + format_number(options.tolerance) + ")");
    if (options.max_iterations < 1) throw Error("the iteration cap must be at least 1");
    for (const auto& p : g.poles)
        if (p.imag() == 0 && p.real() >= 0)
            throw Error("unstable filter: a pole lies at s = " + format_number(p.real()) + " >= 0");
}

void report_progress(const FilterOptions& options, double fraction, const std::string& stage) {
    if (options.progress && !options.progress(fraction, stage)) throw Error("cancelled by the user while " + stage);
}
} // namespace detail

Points apply_filter(const Points& points, const Triangles& triangles, const TransferFunction& g,
                    const FilterOptions& options, FilterReport* report_out) {
    try {
        return apply_filter_unguarded(points, triangles, g, options, report_out);
    } catch (const std::bad_alloc&) {
        throw Error("out of memory while filtering " + std::to_string(points.rows()) +
                    " vertices: close other programs, or simplify the mesh first");
    }
}

namespace {

Points apply_filter_unguarded(const Points& points, const Triangles& triangles, const TransferFunction& g,
                              const FilterOptions& options, FilterReport* report_out) {
    const auto t0 = std::chrono::steady_clock::now();
    detail::check_filter_options(g, options);

    const double budget = options.memory_budget_bytes > 0 ? options.memory_budget_bytes : available_memory_bytes();
    if (budget > 0 && estimated_filter_bytes(points.rows()) > budget)
        throw Error("the mesh is too large for the memory available: filtering " + std::to_string(points.rows()) +
                    " vertices needs about " + gib(estimated_filter_bytes(points.rows())) + ", only " + gib(budget) +
                    " is available; simplify the mesh or free memory");

    FilterReport report;
    report.solver = options.solver;
    const PreparedMesh mesh = prepare_mesh(points, triangles);
    report.warnings = mesh.warnings;
    report.active_vertices = static_cast<int>(mesh.active_vertex.size());

    detail::report_progress(options, 0.0, "assembling the Laplacian");
    const Laplacian laplacian = build_laplacian(options.op, mesh.points, mesh.triangles);
    // Each connected component is centred on its own area-weighted centroid. The constant
    // functions of a component are its eigenmodes at s = 0, so a filter scales the component
    // about that point: centring on one global centroid would let G0 != 1 pull the components
    // together. Centring also keeps the result independent of where the origin is, and free
    // of cancellation on meshes far from it.
    const std::vector<int> component = connected_components(mesh.triangles, mesh.points.rows());
    const int components = component_count(component);
    Eigen::MatrixXd centroids = Eigen::MatrixXd::Zero(components, 3);
    Eigen::VectorXd component_area = Eigen::VectorXd::Zero(components);
    for (Eigen::Index i = 0; i < mesh.points.rows(); ++i) {
        centroids.row(component[i]) += laplacian.mass[i] * mesh.points.row(i);
        component_area[component[i]] += laplacian.mass[i];
    }
    centroids.array().colwise() /= component_area.array();
    Eigen::MatrixXd centred = mesh.points;
    for (Eigen::Index i = 0; i < mesh.points.rows(); ++i) centred.row(i) -= centroids.row(component[i]);
    report.components = components;
    report.seconds_assembly = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    const double size = (mesh.points.colwise().maxCoeff() - mesh.points.colwise().minCoeff()).norm();
    auto solve = [&](const Laplacian& l, const Eigen::MatrixXd& p) {
        const detail::FilterProblem problem{l, p, g, options, size};
        return options.solver == Solver::Factored ? detail::solve_factored(problem, report)
                                                  : detail::solve_jacobi_pcg(problem, report);
    };

    Eigen::MatrixXd filtered;
    const std::vector<bool> on_boundary =
        options.fix_boundary ? boundary_vertices(mesh.triangles, mesh.points.rows()) : std::vector<bool>();
    report.fixed_vertices = static_cast<int>(std::count(on_boundary.begin(), on_boundary.end(), true));
    if (report.fixed_vertices == 0) {
        if (options.fix_boundary) report.warnings.push_back("the mesh has no open boundary: nothing to keep fixed");
        filtered = solve(laplacian, centred);
    } else {
        if (report.fixed_vertices == static_cast<int>(on_boundary.size()))
            throw Error("every vertex lies on the boundary (a strip one triangle wide): with the boundary fixed there"
                        " is nothing to filter; turn fixBoundary off");
        const Eigen::MatrixXd harmonic = harmonic_extension(laplacian, on_boundary, centred);
        std::vector<bool> interior(on_boundary.size());
        for (size_t i = 0; i < interior.size(); ++i) interior[i] = !on_boundary[i];
        Eigen::MatrixXd detail_part(centred.rows() - report.fixed_vertices, 3);
        for (size_t i = 0, k = 0; i < interior.size(); ++i)
            if (interior[i]) detail_part.row(static_cast<Eigen::Index>(k++)) = centred.row(i) - harmonic.row(i);
        const Eigen::MatrixXd detail_filtered = solve(restrict_laplacian(laplacian, interior), detail_part);
        filtered = centred;  // boundary rows stay exactly as they were
        for (size_t i = 0, k = 0; i < interior.size(); ++i)
            if (interior[i]) filtered.row(i) = harmonic.row(i) + detail_filtered.row(static_cast<Eigen::Index>(k++));
    }
    for (Eigen::Index i = 0; i < filtered.rows(); ++i) filtered.row(i) += centroids.row(component[i]);
    if (!filtered.allFinite())
        throw Error("the filter produced non-finite coordinates: the mesh is too degenerate for this filter");

    Points result = points;
    for (size_t i = 0; i < mesh.active_vertex.size(); ++i)
        if (on_boundary.empty() || !on_boundary[i]) result.row(mesh.active_vertex[i]) = filtered.row(i);
    report.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    detail::report_progress(options, 1.0, "done");
    if (report_out) *report_out = std::move(report);
    return result;
}

} // namespace

} // namespace geofilter
