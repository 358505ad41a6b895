// Applying a transfer function to a mesh: p' = V G(Lambda) V^-1 p (paper eq. 8), solved
// without eigenvectors.
#pragma once

#include "core/solve/complex_shifted_factor.h"
#include "core/filter/filter_cache.h"
#include "core/operators/operators.h"
#include "core/design/transfer_function.h"
#include "core/types.h"

#include <functional>
#include <string>
#include <vector>

namespace geofilter {

enum class Solver {
    // Sparse Cholesky (CHOLMOD) of K + c M for each real pole, one factor reused as the
    // preconditioner of the complex-pole pair; independent of s1. The default. A lowpass
    // (G(0) = 1) on the umbrella operator, whose frequencies lie in [0, 2] on any mesh, is
    // applied by the Lanczos process instead (solve/krylov_lowpass.h): a few dozen products
    // with K, to the same error bound, cheaper than one factorisation.
    Factored,
    // The paper's method: Jacobi-preconditioned CG on eq. 9, matrix-free. Slow for small s1.
    JacobiPcg,
};

const char* solver_name(Solver solver);

// Estimated peak memory of apply_filter on a mesh with this many vertices (measured: the
// sparse Cholesky factor dominates, ~1 KB per vertex on surface meshes).
double estimated_filter_bytes(Eigen::Index vertices);

// Receives a fraction in [0, 1] and the current stage; returns false to cancel.
using ProgressCallback = std::function<bool(double fraction, const std::string& stage)>;

struct FilterReport;

// The problem the factored solver solves, for an engine outside the core that solves it the
// same way on other hardware (geofilter-mpi: distributed over MPI ranks). `coordinates` are
// centred (each component about its centroid), `laplacian` has positive mass everywhere, and
// the result, G(M^-1 K) applied to the coordinates, may be off by at most `allowed_error`
// (Frobenius norm in the frame q = M^1/2 p). `laplacian` and `coordinates` are the engine's
// to free once it has built its own form of them (geofilter-mpi's rank 0 would otherwise
// hold both through the factorisation, where its memory peaks).
struct FactoredProblem {
    Laplacian laplacian;
    Eigen::MatrixXd coordinates;
    const TransferFunction& g;
    double allowed_error;
    int max_iterations;
};
using ExternalFactoredSolver = std::function<Eigen::MatrixXd(FactoredProblem&, FilterReport&)>;

struct FilterOptions {
    Solver solver = Solver::Factored;
    Operator op = Operator::Cotangent;  // the Laplacian whose frequencies G is designed in
    // Accuracy of the result: the solvers stop once their error bound guarantees that the
    // area-weighted RMS distance between the computed and the exact filtered surface is below
    // this fraction of the bounding-box diagonal. The bounds follow from the filter's poles
    // (lower bounds on the solved operators' eigenvalues), so they hold on any mesh.
    double tolerance = 1e-7;
    // Keep vertices on open boundaries where they are. The interior is then filtered as
    // p' = h + G(L_D) (p - h): h is the harmonic extension of the boundary, L_D the Laplacian
    // with the boundary fixed (Dirichlet). Off by default: the paper's filter, whose free
    // (natural) boundary lets open edges move with the surface.
    bool fix_boundary = false;
    // Refuse up front when the estimated peak memory exceeds this many bytes; 0 = what the
    // system reports as available (MemAvailable), so that a huge mesh fails in a second
    // with a message instead of minutes later in the allocator.
    double memory_budget_bytes = 0;
    int max_iterations = 100000;   // cap per iterative solve; hitting it is an error
    ProgressCallback progress;
    // Runs the factored solver's algorithm instead of the core's (Solver::Factored only);
    // empty: the core's own.
    ExternalFactoredSolver external_solver;
    // How the factored solver may factorise Kt - r I for a complex pole pair r, conj r, to
    // solve the pair exactly where CG on it is predicted to cost more (sharp resonances:
    // notch, exaggeration, high-order Butterworth); empty: every pair by CG.
    ComplexShiftedFactorization complex_factorization;
};

struct FilterReport {
    Solver solver = Solver::Factored;
    int active_vertices = 0;
    int iterations = 0;            // CG iterations, summed over the solves that iterate
    double relative_residual = 0;  // worst relative residual of eq. 9 / the factor solves
    double seconds_assembly = 0, seconds_factorization = 0, seconds_solve = 0, seconds_total = 0;
    int fixed_vertices = 0;        // boundary vertices kept in place (fix_boundary)
    int components = 0;            // connected components, each filtered about its own centroid
    std::vector<std::string> warnings;  // repairs made to the input, in plain words
    // What came from a FilterCache: "" (nothing), "mesh" (checks, Laplacian, analysis),
    // "mesh and factor", "operator" or "operator and factor" (other coordinates on the same
    // triangles, for an operator that ignores positions), or "result" (the same filter as the
    // run before).
    std::string reused;
    // Set by an ExternalFactoredSolver that solved in its own way (geofilter-mpi's multigrid
    // option), so that the log does not claim a factorisation that never happened.
    std::string external_solver;
    int krylov_steps = 0;           // > 0: solved by the Lanczos process in this many steps, no factorisation
    int exact_pairs = 0;            // complex pole pairs solved by a factorisation of Kt - r I, not CG
    std::string exact_pair_method;  // that factorisation, in words
    int exact_pair_refinements = 0; // solves with that factor beyond one per pair
    std::string exact_pair_note;    // why a pair predicted to pay was solved by CG after all
    int poles_at_one_shift = 0;     // poles solved together from one factor's Krylov space (a Butterworth's)
};

// The solver that produced a report, in words for the log.
std::string solver_used(const FilterReport& report);

// Filters every vertex that belongs to a usable face; other vertices keep their position.
// Each connected component is filtered about its own area-weighted centroid, so the result
// does not depend on where the origin is, G(0) = G0 scales each component about its centroid,
// and components never pull on each other. Throws Error on bad input, an
// unstable transfer function, non-convergence or cancellation; never returns a partial result.
// With a cache, a run on the same mesh (same points, faces, operator and boundary option)
// reuses what earlier runs built; the result meets the same tolerance either way.
Points apply_filter(const Points& points, const Triangles& triangles, const TransferFunction& g,
                    const FilterOptions& options = {}, FilterReport* report = nullptr, FilterCache* cache = nullptr);

// The filter with the vertices marked in `held` (one flag per vertex; empty: none) kept where
// they are and the others filtered as the Dirichlet problem p' = h + G(L_D)(p - h), h the
// harmonic extension of the held vertices (what fix_boundary does for open boundaries). A
// region is filtered this way (region.h): its sub-mesh, with the ring around it held.
// report->active_vertices counts the vertices not held. With every vertex held (or on a
// fixed boundary) the points come back as given, with a warning.
Points apply_filter_with_held(const Points& points, const Triangles& triangles, const std::vector<bool>& held,
                              const TransferFunction& g, const FilterOptions& options = {},
                              FilterReport* report = nullptr, FilterCache* cache = nullptr);

// The same filter applied to a field on the vertices instead of their coordinates: G(M^-1 K)
// f with the operator of `points`, one column at a time (e.g. what a lowpass of the mesh
// keeps of a displacement). Vertices in no usable face keep their value; with fix_boundary
// the boundary rows too. Errors are in the field's units, bounded like apply_filter's.
Eigen::MatrixXd filter_field(const Points& points, const Triangles& triangles, const TransferFunction& g,
                             const Eigen::MatrixXd& field, const FilterOptions& options = {},
                             FilterReport* report = nullptr);

} // namespace geofilter
