// Sparse Cholesky factors of Kt + shift I that share one symbolic analysis: every shift has
// the same sparsity, so the fill-reducing ordering is computed once per Laplacian, and a
// factor stays available for the next solve (or the next filter run) at the same shift.
// Internal to the core.
#pragma once

#include "core/solve/complex_shifted_factor.h"
#include "core/solve/exact_pair.h"
#include "core/operators/laplace.h"
#include "core/solve/supernodal_solve.h"

#include <Eigen/CholmodSupport>

#include <cmath>
#include <string>
#include <vector>

namespace geofilter::detail {

class ShiftedCholesky {
public:
    // `kt` must outlive this object.
    explicit ShiftedCholesky(const SparseMatrix& kt) : kt_(kt) {}
    ShiftedCholesky(const ShiftedCholesky&) = delete;
    ShiftedCholesky& operator=(const ShiftedCholesky&) = delete;

    // The fill-reducing ordering and the symbolic factor of Kt's pattern, once: not before
    // the first factorisation, because a filter whose pairs are all solved exactly needs
    // none (at 1M vertices AMD takes 0.4-1.5 s and its symbolic factor ~55 bytes a vertex).
    void analyse();
    bool analysed() const { return analysed_; }
    // Makes the factor of Kt + shift I current, computing it unless it is already held
    // (analysing first if that was not done).
    void factorize(double shift);
    bool has_factor() const { return !std::isnan(shift_); }
    double shift() const { return shift_; }
    // (Kt + shift I)^-1 b with the current factor.
    Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const { return solve_supernodal(llt_.factor(), b); }

private:
    const SparseMatrix& kt_;
    SupernodalCholesky llt_;
    bool analysed_ = false;
    double shift_ = NAN;
};

// What the factored solver builds for one Laplacian before any filter-specific work: the
// symmetric frame q = M^1/2 p, Kt, and its factorisation (analysed when first needed). A FilterCache keeps it
// between runs on the same mesh, with the costs measured so far, which decide whether a
// held factor at another shift is worth reusing as a preconditioner.
struct FactorState {
    explicit FactorState(const Laplacian& laplacian);
    FactorState(const FactorState&) = delete;
    FactorState& operator=(const FactorState&) = delete;

    Eigen::VectorXd sqrt_mass;
    SparseMatrix kt;
    ShiftedCholesky cholesky;       // constructed after kt, which it refers to
    ExactPairState exact;           // exact pair solves: the complex factor, built when first used
    double seconds_per_factorization = 0;   // the last numeric factorisation; 0 = none yet
    double seconds_per_pair_iteration = 0;  // the last conjugate-pair CG run; 0 = none yet
    int last_pair_iterations = 0;           // its iterations
    double last_pair_rate = 0;              // and its convergence rate (shifted_pair_rate)
    // The last run's CG pair solutions, in the order solved (kept only in a FilterCache): the
    // next run's pairs start from them (a preview's parameter change barely moves them).
    std::vector<Eigen::MatrixXd> pair_solutions;
};

} // namespace geofilter::detail
