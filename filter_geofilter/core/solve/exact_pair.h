// A complex pole pair solved exactly: ((Kt - r)(Kt - conj r))^-1 y = Im((Kt - r)^-1 y) / Im r,
// with a factorisation of the complex symmetric Kt - r I (complex_shifted_factor.h), and the
// rule that decides when that beats CG preconditioned with a real factor. Shared by the core's
// factored solver and geofilter-mpi's distributed one, so that both take the same decision.
#pragma once

#include "core/solve/complex_shifted_factor.h"
#include "core/filter/filter.h"
#include "core/solve/pcg.h"
#include "core/design/transfer_function.h"

#include <complex>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace geofilter::detail {

// The shortest factorisation whose time stands for the solver's costs (below it, the
// default ratios of PairSolveCosts decide): 50 ms, a mesh of some 20k vertices.
constexpr double least_timed_factorization_seconds = 0.05;

// What the two ways of solving a pair cost, in any one unit. The defaults are ratios to one
// real factorisation of Kt + c I: the exact pair, a single-precision complex LDL^T refined in
// double (what the adapters and geofilter-mpi factorise), 1.56-1.66 with its solves (1.6
// taken), measured on the 384k-vertex diplodocus, the 1M torus and the 1.1M man (medians of
// three alternated runs of tests/benchmark/benchmark_complex_pole.cpp, the lowpass); one
// iteration of the shifted CG (shifted_pair_cg.h), one solve with the real factor: half of the
// 0.09-0.13 measured in the same runs for an iteration of CG on the real pair, which made two
// (0.07 taken); their count from shifted_pair_iterations. A solver that has timed its own
// steps passes those instead.
struct PairSolveCosts {
    double real_factorization = 1.0;
    double complex_factorization = 1.6;
    double pair_iteration = 0.07;
    // A previous CG pair solve on this mesh, to scale the iteration count from (0: none).
    int last_pair_iterations = 0;
    double last_pair_rate = 0;
    // The run keeps its factors for the next (a FilterCache: MeshLab's Preview). The next
    // parameter change moves r: a held real factor then serves the shifted CG at the new r
    // with no factorisation (5-17 iterations measured at 17k-280k vertices), while a complex
    // factor serves only the same r and is made again. So a session charges the real factor
    // as held and the complex one twice (this run and the next change): sharp pairs (notch,
    // exaggeration) still go exact, the lowpass stays on CG (its Preview change at 100k took
    // 0.96 s exact against 0.32-0.48 s on CG on the real pair, 0.20-0.29 s now).
    bool session = false;
};

// Whether factorising Kt - r I is predicted to cost less than CG preconditioned with the real
// factor at `shift` (whose factorisation counts only if it is not held already, and not in
// a session). Never when
// another pole group of `g` needs the real factor at that shift anyway (a real pole, or
// another pair: a Butterworth's poles all lie on the circle |r| = sc). Measured on the 1M
// torus, an order-8 Butterworth with its sharpest pair exact and the rest on CG took 38.9 s
// and 3.1 GB (both factors held at once) against 30.2 s and 1.5 GB with every pair on CG.
bool exact_pair_pays(const TransferFunction& g, std::complex<double> r, double shift, bool real_factor_held,
                     const PairSolveCosts& costs);

// The global Frobenius norm of a block of rows (a distributed solver reduces over its ranks).
using BlockNorm = std::function<double(const Eigen::MatrixXd&)>;

struct ExactPairSolution {
    Eigen::MatrixXd x;
    double relative_residual = 0;  // of the complex system, after refinement
    int refinements = 0;           // solves with the factor beyond the first
};

// Im(z) / Im r for z = (Kt - r)^-1 y, with `factor` holding Kt - r I, refined with the
// double-precision residual rho = y - (Kt - r) z until its error bound meets allowed_error.
// The spectrum of Kt being real and non-negative, the error in z is at most |rho| / d with
// d = min over s >= 0 of |s - r|, and in the pair at most that over Im r: a bound, as CG's.
// When a refinement gains less than a factor 10, or after 6, the factor's precision is raised
// (factor.raise_precision()) and the solve starts again; throws Error when it cannot be.
// Collective when `kt_times`, `norm` and the factor are.
ExactPairSolution solve_pair_exactly(ComplexShiftedFactor& factor, std::complex<double> r, const Eigen::MatrixXd& y,
                                     double allowed_error, const BlockOperator& kt_times, const BlockNorm& norm);

// A solver's exact pair solves: the factor holder, made when first needed, and once an exact
// solve failed, why (every later pair on this state then goes to CG).
struct ExactPairState {
    std::unique_ptr<ComplexShiftedFactor> factor;
    std::string note;
    double seconds_per_factorization = 0;  // the last complex factorisation; 0 = none yet

    bool failed() const { return !note.empty(); }
    bool holds(std::complex<double> r) const { return factor && factor->holds(r); }
};

// What differs from solver to solver: how the factor holder is made, whether a factorisation
// of that many bytes fits ("" when it does, else why not), Kt times a block of rows, the
// global norm, and progress (may be empty). Collective where the solver is distributed.
struct ExactPairSteps {
    std::function<std::unique_ptr<ComplexShiftedFactor>()> make_factor;
    std::function<std::string(double bytes)> memory_shortfall;
    BlockOperator kt_times;
    BlockNorm norm;
    std::function<void(const char* stage)> progress;
};

// The pair by solve_pair_exactly with the state's factor, made and factorised at r as needed;
// the times, residual and method go into `report`. Empty when that fails or would not fit in
// memory: the factor is released (its memory goes back before CG needs its own), state.note
// and report.exact_pair_note say why, and CG solves this pair and every later one.
std::optional<Eigen::MatrixXd> solve_pair_exactly_or_explain(ExactPairState& state, const ExactPairSteps& steps,
                                                             std::complex<double> r, const Eigen::MatrixXd& y,
                                                             double allowed_error, FilterReport& report);

} // namespace geofilter::detail
