#include "core/mesh/boundary.h"
#include "core/solve/pcg.h"
#include "core/mesh/components.h"
#include "core/mesh/mesh_prep.h"
#include "core/operators/operators.h"
#include "core/solve/krylov_lowpass.h"
#include "core/solve/shifted_cholesky.h"
#include "core/solve/solvers.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <new>
#include <optional>

namespace geofilter {

namespace {
Points apply_filter_unguarded(const Points& points, const Triangles& triangles, const std::vector<bool>& held,
                              const TransferFunction& g,
                              const FilterOptions& options, FilterReport* report_out, FilterCache* cache);
} // namespace

const char* solver_name(Solver solver) {
    return solver == Solver::Factored ? "factored (sparse Cholesky)" : "Jacobi-PCG on eq. 9 (paper)";
}

std::string solver_used(const FilterReport& report) {
    if (report.krylov_steps > 0)
        return "Lanczos process (" + std::to_string(report.krylov_steps) + " steps on the umbrella operator, no factorisation)";
    std::string used = report.external_solver.empty() ? solver_name(report.solver) : report.external_solver;
    if (report.exact_pairs > 0)
        used += "; " + std::to_string(report.exact_pairs) + " complex pole pair(s) solved exactly by " +
                report.exact_pair_method + " with " + std::to_string(report.exact_pair_refinements) + " refinement(s)";
    if (report.poles_at_one_shift > 0)
        used += "; its " + std::to_string(report.poles_at_one_shift) + " poles solved together with one factor";
    if (!report.exact_pair_note.empty()) used += "; " + report.exact_pair_note;
    return used;
}

double estimated_filter_bytes(Eigen::Index vertices) { return 1500.0 * static_cast<double>(vertices); }

double detail::available_memory_bytes() {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    double kib = 0;
    std::string unit;
    while (meminfo >> key >> kib >> unit)
        if (key == "MemAvailable:") return kib * 1024.0;
    return 0;  // unknown: no up-front check
}

namespace {

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

namespace detail {

// Everything a filter run builds before it looks at the transfer function.
struct MeshStage {
    // What it was built from.
    Points input_points;
    Triangles input_triangles;
    Operator op;
    bool fix_boundary;
    std::vector<bool> held;  // input vertices kept where they are (empty: none)

    PreparedMesh mesh;
    Laplacian laplacian;
    std::vector<int> component;
    int components = 0;
    Eigen::MatrixXd centroids;
    double size = 0;
    // Rows kept where they are: the open boundary with fix_boundary, and the held vertices.
    // Empty when there are none.
    std::vector<bool> fixed;
    int fixed_vertices = 0;  // of them, open-boundary vertices that were not held
    int held_vertices = 0;
    bool all_fixed = false;  // every row held or on a fixed boundary: nothing to filter
    std::vector<std::string> warnings;
    // What the solver filters: the centred coordinates with the whole Laplacian, or, with
    // the boundary fixed, the detail above the harmonic extension with the interior's
    // Dirichlet Laplacian.
    Eigen::MatrixXd centred, harmonic, solved_coordinates;
    std::optional<Laplacian> interior;
    std::unique_ptr<FactorState> factors;

    struct Result {
        TransferFunction g;
        Solver solver;
        double tolerance;
        int max_iterations;
        Points points;
        FilterReport report;
    };
    std::optional<Result> last;

    const Laplacian& solved_laplacian() const { return interior ? *interior : laplacian; }

    bool built_from(const Points& points, const Triangles& triangles, const std::vector<bool>& other_held,
                    const FilterOptions& options) const {
        return op == options.op && fix_boundary == options.fix_boundary && held == other_held &&
               input_points.rows() == points.rows() && input_triangles.rows() == triangles.rows() &&
               input_points == points && input_triangles == triangles;
    }
};

} // namespace detail

FilterCache::FilterCache(Eigen::Index max_vertices) : max_vertices_(max_vertices) {}
FilterCache::~FilterCache() = default;
void FilterCache::clear() { stage_.reset(); }

Points apply_filter(const Points& points, const Triangles& triangles, const TransferFunction& g,
                    const FilterOptions& options, FilterReport* report_out, FilterCache* cache) {
    return apply_filter_with_held(points, triangles, {}, g, options, report_out, cache);
}

Points apply_filter_with_held(const Points& points, const Triangles& triangles, const std::vector<bool>& held,
                              const TransferFunction& g, const FilterOptions& options, FilterReport* report_out,
                              FilterCache* cache) {
    if (!held.empty() && static_cast<Eigen::Index>(held.size()) != points.rows())
        throw Error("internal: " + std::to_string(held.size()) + " held flags for " + std::to_string(points.rows()) +
                    " vertices");
    try {
        return apply_filter_unguarded(points, triangles, held, g, options, report_out, cache);
    } catch (const std::bad_alloc&) {
        if (cache) cache->clear();
        throw Error("out of memory while filtering " + std::to_string(points.rows()) +
                    " vertices: close other programs, or simplify the mesh first");
    }
}

namespace {

bool same_function(const TransferFunction& a, const TransferFunction& b) {
    auto same_coefficients = [](const std::optional<SecondOrderCoefficients>& x,
                                const std::optional<SecondOrderCoefficients>& y) {
        if (x.has_value() != y.has_value()) return false;
        return !x || (x->a0 == y->a0 && x->a1 == y->a1 && x->a2 == y->a2 && x->b0 == y->b0 && x->b1 == y->b1 &&
                      x->b2 == y->b2);
    };
    return a.gain == b.gain && a.numerator == b.numerator && a.poles == b.poles &&
           same_coefficients(a.second_order, b.second_order);
}

void place_coordinates(detail::MeshStage& st, const FilterOptions& options);
void split_at_fixed_boundary(detail::MeshStage& st, const FilterOptions& options);

// The inverse of split_at_fixed_boundary: the solver's rows back on every vertex, the fixed
// boundary's rows exactly as they were.
Eigen::MatrixXd join_at_fixed_boundary(const detail::MeshStage& st, const Eigen::MatrixXd& solved) {
    if (st.fixed.empty()) return solved;
    Eigen::MatrixXd joined = st.centred;
    for (size_t i = 0, k = 0; i < st.fixed.size(); ++i)
        if (!st.fixed[i]) joined.row(i) = st.harmonic.row(i) + solved.row(static_cast<Eigen::Index>(k++));
    return joined;
}

// What a run's report says of the mesh before anything is solved.
FilterReport report_for(const detail::MeshStage& st, const FilterOptions& options) {
    FilterReport report;
    report.solver = options.solver;
    report.warnings = st.warnings;
    report.active_vertices = static_cast<int>(st.mesh.active_vertex.size()) - st.held_vertices;
    report.components = st.components;
    report.fixed_vertices = st.fixed_vertices;
    return report;
}

std::unique_ptr<detail::MeshStage> build_mesh_stage(const Points& points, const Triangles& triangles,
                                                    const std::vector<bool>& held, const FilterOptions& options,
                                                    bool keep_input) {
    auto stage = std::make_unique<detail::MeshStage>();
    detail::MeshStage& st = *stage;
    if (keep_input) {
        st.input_points = points;
        st.input_triangles = triangles;
    }
    st.op = options.op;
    st.fix_boundary = options.fix_boundary;
    st.held = held;
    st.mesh = prepare_mesh(points, triangles);
    const PreparedMesh& mesh = st.mesh;

    detail::report_progress(options, 0.0, "assembling the Laplacian");
    st.laplacian = build_laplacian(options.op, mesh.points, mesh.triangles);
    st.component = connected_components(mesh.triangles, mesh.points.rows());
    st.components = component_count(st.component);
    place_coordinates(st, options);
    return stage;
}

// The part of a stage that depends on the coordinates and not on the operator: each
// component's centroid, the centred coordinates, the size, the fixed boundary's harmonic
// extension and what the solver filters.
void place_coordinates(detail::MeshStage& st, const FilterOptions& options) {
    const PreparedMesh& mesh = st.mesh;
    st.warnings = mesh.warnings;
    // Each connected component is centred on its own area-weighted centroid. The constant
    // functions of a component are its eigenmodes at s = 0, so a filter scales the component
    // about that point: centring on one global centroid would let G0 != 1 pull the components
    // together. Centring also keeps the result independent of where the origin is, and free
    // of cancellation on meshes far from it.
    st.centroids = Eigen::MatrixXd::Zero(st.components, 3);
    Eigen::VectorXd component_area = Eigen::VectorXd::Zero(st.components);
    for (Eigen::Index i = 0; i < mesh.points.rows(); ++i) {
        st.centroids.row(st.component[i]) += st.laplacian.mass[i] * mesh.points.row(i);
        component_area[st.component[i]] += st.laplacian.mass[i];
    }
    st.centroids.array().colwise() /= component_area.array();
    st.centred = mesh.points;
    for (Eigen::Index i = 0; i < mesh.points.rows(); ++i) st.centred.row(i) -= st.centroids.row(st.component[i]);
    st.size = bounding_box_diagonal(mesh.points);
    split_at_fixed_boundary(st, options);
}

// What the solver filters, from st.centred: all of it, or, with rows held fixed (the open
// boundary with fix_boundary, the held vertices), the part above their harmonic extension on
// the other rows.
void split_at_fixed_boundary(detail::MeshStage& st, const FilterOptions& options) {
    const PreparedMesh& mesh = st.mesh;
    const size_t n = mesh.active_vertex.size();
    const std::vector<bool> boundary = options.fix_boundary ? boundary_vertices(mesh.triangles, mesh.points.rows())
                                                            : std::vector<bool>(n, false);
    st.fixed.assign(n, false);
    st.fixed_vertices = st.held_vertices = 0;
    for (size_t i = 0; i < n; ++i) {
        const bool held = !st.held.empty() && st.held[static_cast<size_t>(mesh.active_vertex[i])];
        st.held_vertices += held;
        st.fixed_vertices += !held && boundary[i];
        st.fixed[i] = held || boundary[i];
    }
    const int fixed_rows = st.fixed_vertices + st.held_vertices;
    st.all_fixed = false;
    if (fixed_rows == 0) {
        st.fixed.clear();
        if (options.fix_boundary && st.held.empty()) st.warnings.push_back("the mesh has no open boundary: nothing to keep fixed");
        st.solved_coordinates = st.centred;
        return;
    }
    if (fixed_rows == static_cast<int>(n)) {
        if (st.held_vertices == 0)
            throw Error("every vertex lies on the boundary (a strip one triangle wide): with the boundary fixed there"
                        " is nothing to filter; turn fixBoundary off");
        st.all_fixed = true;
        st.warnings.push_back("every vertex is held fixed (by the region's border or fixBoundary): nothing changed");
        return;
    }
    st.harmonic = harmonic_extension(st.laplacian, st.fixed, st.centred);
    std::vector<bool> interior(n);
    for (size_t i = 0; i < n; ++i) interior[i] = !st.fixed[i];
    st.solved_coordinates.resize(st.centred.rows() - fixed_rows, st.centred.cols());
    for (size_t i = 0, k = 0; i < n; ++i)
        if (interior[i]) st.solved_coordinates.row(static_cast<Eigen::Index>(k++)) = st.centred.row(i) - st.harmonic.row(i);
    if (!st.interior) st.interior = restrict_laplacian(st.laplacian, interior);
}

// A kept stage whose operator ignores the positions (the umbrella) serves other coordinates
// on the same triangles, as Denoise's perturbed runs need: only place_coordinates is redone,
// and the Laplacian, its factors and the last pair solutions (CG's starting points) stay.
// False, and nothing changed, when the operator or the usable faces would differ.
bool rebind_coordinates(detail::MeshStage& st, const Points& points, const Triangles& triangles,
                        const std::vector<bool>& held, const FilterOptions& options) {
    if (operator_uses_positions(st.op) || st.op != options.op || st.fix_boundary != options.fix_boundary || st.held != held ||
        st.input_points.rows() != points.rows() || st.input_triangles.rows() != triangles.rows() ||
        st.input_triangles != triangles)
        return false;
    PreparedMesh mesh = prepare_mesh(points, triangles);
    if (mesh.active_vertex != st.mesh.active_vertex || mesh.triangles != st.mesh.triangles) return false;
    st.input_points = points;
    st.mesh = std::move(mesh);
    st.last.reset();
    place_coordinates(st, options);
    return true;
}

// A lowpass on the umbrella operator through the Lanczos process (Solver::Factored's note),
// to the solvers' own allowed error; nothing when it does not apply or did not converge in
// a bounded number of steps (the factored solver then runs).
std::optional<Eigen::MatrixXd> solve_by_krylov(const detail::MeshStage& st, const detail::FilterProblem& problem,
                                               FilterReport& report) {
    constexpr int max_steps = 500;
    const TransferFunction& g = problem.g;
    if (problem.options.solver != Solver::Factored || st.op != Operator::Umbrella || !krylov_lowpass_applies(g))
        return std::nullopt;
    const auto t0 = std::chrono::steady_clock::now();
    detail::report_progress(problem.options, 0.1, "applying the lowpass by the Lanczos process");
    KrylovReport krylov;
    Eigen::MatrixXd solved =
        krylov_lowpass(problem.laplacian, problem.coordinates, g, detail::allowed_error(problem), max_steps, &krylov);
    if (!krylov.converged) return std::nullopt;
    report.krylov_steps = krylov.iterations;
    report.seconds_solve = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return solved;
}

Points apply_filter_unguarded(const Points& points, const Triangles& triangles, const std::vector<bool>& held,
                              const TransferFunction& g, const FilterOptions& options, FilterReport* report_out,
                              FilterCache* cache) {
    const auto t0 = std::chrono::steady_clock::now();
    detail::check_filter_options(g, options);

    const bool cacheable = cache && points.rows() <= cache->max_vertices();
    std::unique_ptr<detail::MeshStage> local;
    std::unique_ptr<detail::MeshStage>& slot = cacheable ? cache->stage() : local;
    if (cache && !cacheable) cache->clear();
    const bool same_mesh = slot && slot->built_from(points, triangles, held, options);
    const bool rebound = !same_mesh && cacheable && slot && rebind_coordinates(*slot, points, triangles, held, options);
    const bool reuse_mesh = same_mesh || rebound;
    if (!reuse_mesh) {
        slot.reset();  // free the old mesh's factors before building the new ones
        const double budget = options.memory_budget_bytes > 0 ? options.memory_budget_bytes : detail::available_memory_bytes();
        if (budget > 0 && estimated_filter_bytes(points.rows()) > budget)
            throw Error("the mesh is too large for the memory available: filtering " + std::to_string(points.rows()) +
                        " vertices needs about " + gib(estimated_filter_bytes(points.rows())) + ", only " + gib(budget) +
                        " is available; simplify the mesh or free memory");
        slot = build_mesh_stage(points, triangles, held, options, cacheable);
    }
    detail::MeshStage& st = *slot;
    if (st.all_fixed) {
        FilterReport report = report_for(st, options);
        report.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        detail::report_progress(options, 1.0, "done");
        if (report_out) *report_out = std::move(report);
        return points;
    }

    if (reuse_mesh && st.last && st.last->solver == options.solver && st.last->tolerance == options.tolerance &&
        st.last->max_iterations == options.max_iterations && same_function(st.last->g, g)) {
        FilterReport report = st.last->report;
        report.reused = "result";
        report.seconds_assembly = report.seconds_factorization = report.seconds_solve = 0;
        report.iterations = 0;
        report.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        detail::report_progress(options, 1.0, "done");
        if (report_out) *report_out = std::move(report);
        return st.last->points;
    }

    FilterReport report = report_for(st, options);
    const bool had_factor = st.factors && st.factors->cholesky.has_factor();
    report.seconds_assembly = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    detail::FilterProblem problem{st.solved_laplacian(), st.solved_coordinates, g, options, st.size};
    if (cacheable) problem.factor_slot = &st.factors;
    Eigen::MatrixXd solved;
    // The Lanczos process comes first, also when an external engine (geofilter-mpi) is given:
    // it factorises nothing, so the engine has nothing to distribute, and every front end
    // then gives the same coordinates.
    if (std::optional<Eigen::MatrixXd> by_krylov = solve_by_krylov(st, problem, report)) {
        solved = std::move(*by_krylov);
    } else if (options.solver == Solver::Factored && options.external_solver) {
        FactoredProblem handed{{}, {}, g, detail::allowed_error(problem), options.max_iterations};
        // Without a cache nothing reads the solved Laplacian and coordinates after the solve:
        // the engine gets them, not copies (swapped: Eigen's sparse matrix has no move).
        Laplacian& laplacian = st.interior ? *st.interior : st.laplacian;
        if (cacheable) {
            handed.laplacian = laplacian;
            handed.coordinates = st.solved_coordinates;
        } else {
            handed.laplacian.stiffness.swap(laplacian.stiffness);
            handed.laplacian.mass.swap(laplacian.mass);
            handed.coordinates.swap(st.solved_coordinates);
            // Nor the prepared mesh's copies (nor the centred one without a fixed boundary),
            // which would otherwise sit through the engine's factorisation.
            st.mesh.points.resize(0, 0);
            st.mesh.triangles.resize(0, 0);
            if (st.fixed.empty()) st.centred.resize(0, 0);
            if (st.interior) {  // the whole Laplacian too: the interior one is what was handed over
                SparseMatrix().swap(st.laplacian.stiffness);
                st.laplacian.mass.resize(0);
            }
        }
        solved = options.external_solver(handed, report);
    } else {
        solved = options.solver == Solver::Factored ? detail::solve_factored(problem, report)
                                                    : detail::solve_jacobi_pcg(problem, report);
    }
    if (reuse_mesh) {
        const char* kept = rebound ? "operator" : "mesh";
        report.reused = std::string(kept) + (had_factor && report.seconds_factorization == 0 ? " and factor" : "");
    }

    Eigen::MatrixXd filtered = join_at_fixed_boundary(st, solved);
    for (Eigen::Index i = 0; i < filtered.rows(); ++i) filtered.row(i) += st.centroids.row(st.component[i]);
    if (!filtered.allFinite())
        throw Error("the filter produced non-finite coordinates: the mesh is too degenerate for this filter");

    Points result = points;
    for (size_t i = 0; i < st.mesh.active_vertex.size(); ++i)
        if (st.fixed.empty() || !st.fixed[i]) result.row(st.mesh.active_vertex[i]) = filtered.row(i);
    report.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    detail::report_progress(options, 1.0, "done");
    if (cacheable) st.last = detail::MeshStage::Result{g, options.solver, options.tolerance, options.max_iterations, result, report};
    if (report_out) *report_out = std::move(report);
    return result;
}

} // namespace

Eigen::MatrixXd filter_field(const Points& points, const Triangles& triangles, const TransferFunction& g,
                             const Eigen::MatrixXd& field, const FilterOptions& options, FilterReport* report_out) {
    if (field.rows() != points.rows() || field.cols() < 1)
        throw Error("the field to filter has " + std::to_string(field.rows()) + " rows and " +
                    std::to_string(field.cols()) + " columns; it needs one row per vertex (" +
                    std::to_string(points.rows()) + ") and at least one column");
    if (!field.allFinite()) throw Error("the field to filter has a NaN or infinite value");
    detail::check_filter_options(g, options);
    const auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<detail::MeshStage> stage = build_mesh_stage(points, triangles, {}, options, false);
    detail::MeshStage& st = *stage;
    // The field as it is, not about a centroid: constants are eigenmodes at s = 0, which G
    // scales by G0 like any other.
    st.centred.resize(static_cast<Eigen::Index>(st.mesh.active_vertex.size()), field.cols());
    for (size_t i = 0; i < st.mesh.active_vertex.size(); ++i)
        st.centred.row(static_cast<Eigen::Index>(i)) = field.row(st.mesh.active_vertex[i]);
    st.warnings = st.mesh.warnings;
    split_at_fixed_boundary(st, options);

    FilterReport report = report_for(st, options);
    detail::FilterProblem problem{st.solved_laplacian(), st.solved_coordinates, g, options, st.size};
    const Eigen::MatrixXd solved = options.solver == Solver::Factored ? detail::solve_factored(problem, report)
                                                                      : detail::solve_jacobi_pcg(problem, report);
    const Eigen::MatrixXd filtered = join_at_fixed_boundary(st, solved);
    Eigen::MatrixXd result = field;
    for (size_t i = 0; i < st.mesh.active_vertex.size(); ++i)
        result.row(st.mesh.active_vertex[i]) = filtered.row(static_cast<Eigen::Index>(i));
    report.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (report_out) *report_out = std::move(report);
    return result;
}

} // namespace geofilter
