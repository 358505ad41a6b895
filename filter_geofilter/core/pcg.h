// Preconditioned conjugate gradients on several right-hand sides at once (x, y, z):
// each column runs its own CG recurrence, the matrix products are shared.
#pragma once

#include "types.h"

#include <functional>

namespace geofilter {

using BlockOperator = std::function<void(const Eigen::MatrixXd& in, Eigen::MatrixXd& out)>;
// Called every few iterations with the worst relative residual; return false to cancel.
using IterationObserver = std::function<bool(int iteration, double relative_residual)>;

struct PcgOutcome {
    int iterations = 0;
    double relative_residual = 0;  // max over columns of |b - A x| / |b| (recurrence residual)
    bool converged = false;
    bool converged_by_step = false;  // stopped by `step_small`, not by the residual
    bool cancelled = false;
};

// Given the last update of x (one column per right-hand side), says whether the
// remaining error is small enough to stop.
using StepTest = std::function<bool(const Eigen::MatrixXd& step)>;

// Solves A x = b for SPD A. `x` holds the initial guess on entry. Stops when every
// column's relative residual is below `tolerance`, when `step_small` accepts two updates
// in a row, or after `max_iterations`.
PcgOutcome block_pcg(const BlockOperator& apply_matrix, const BlockOperator& apply_preconditioner,
                     const Eigen::MatrixXd& b, Eigen::MatrixXd& x, double tolerance, int max_iterations,
                     const IterationObserver& observer = {}, const StepTest& step_small = {});

} // namespace geofilter
