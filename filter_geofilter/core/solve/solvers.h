// The two ways of applying a transfer function to coordinates; internal to the core.
#pragma once

#include "core/filter/filter.h"
#include "core/operators/laplace.h"
#include "core/solve/pcg.h"

#include <cholmod.h>

#include <memory>

namespace geofilter::detail {

struct FactorState;

// Inputs shared by the solvers. `coordinates` are centred; `laplacian` has positive mass
// at every vertex.
struct FilterProblem {
    const Laplacian& laplacian;
    const Eigen::MatrixXd& coordinates;
    const TransferFunction& g;
    const FilterOptions& options;
    double size;  // bounding-box diagonal of the filtered vertices
    // Where the factored solver finds (or leaves) its Kt and factors for `laplacian`, so that
    // a later run on the same mesh can reuse them; null: built and dropped within the run.
    std::unique_ptr<FactorState>* factor_slot = nullptr;
};

// The error the solvers may leave, as a Frobenius norm in the frame q = M^1/2 p: there it is
// the area-weighted L2 norm of the displacement error, so dividing by sqrt(area) gives the
// area-weighted RMS error that FilterOptions::tolerance bounds (as a fraction of `size`).
double allowed_error(const FilterProblem& problem);

Eigen::MatrixXd solve_factored(const FilterProblem& problem, FilterReport& report);
Eigen::MatrixXd solve_jacobi_pcg(const FilterProblem& problem, FilterReport& report);

// Horner: c_n Kt^n y + ... + c_0 y (c ascending).
Eigen::MatrixXd apply_polynomial(const SparseMatrix& kt, const std::vector<double>& c, const Eigen::MatrixXd& y);

// What /proc/meminfo reports as available (MemAvailable), in bytes; 0 if unknown.
double available_memory_bytes();

// The fill-reducing ordering every CHOLMOD factorisation of the project uses.
void use_amd_ordering(cholmod_common& common);

// Adds a CG run to the report; throws Error if it was cancelled or did not converge
// (`advice` ends the message: what the user can change).
void record_pcg_outcome(const PcgOutcome& outcome, double allowed_error, const std::string& advice, FilterReport& report);

// Refuses options and transfer functions no solver can run (tolerance, iteration cap, a
// real pole on s >= 0), before any work is done.
void check_filter_options(const TransferFunction& g, const FilterOptions& options);

// Throws Error naming the stage if the user cancelled through the progress callback.
void report_progress(const FilterOptions& options, double fraction, const std::string& stage);

} // namespace geofilter::detail
