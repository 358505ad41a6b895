// Preconditioned conjugate gradients on several right-hand sides at once (x, y, z):
// each column runs its own CG recurrence, the matrix products are shared.
#pragma once

#include "core/types.h"

#include <functional>

namespace geofilter {

using BlockOperator = std::function<void(const Eigen::MatrixXd& in, Eigen::MatrixXd& out)>;
// Called every few iterations with the current error bound; return false to cancel.
using IterationObserver = std::function<bool(int iteration, double error_bound)>;

// A guaranteed bound on the error |x - A^-1 b| (in whatever norm and units the caller
// stops on), from the residual r = b - A x and, per column, r.z with z = P^-1 r. It must
// hold for every x: the bound decides when to stop, so it has to follow from what is known
// of A and P (e.g. bounds on their eigenvalues), not from the iterates' history.
using ErrorBound = std::function<double(const Eigen::MatrixXd& residual, const Eigen::ArrayXd& rz)>;

// Turns per-column sums over this caller's rows into sums over all rows, in place: a caller
// that holds only its share of the rows (a distributed solve) adds up the other shares here,
// so that every part takes the same steps. Empty: the rows given are all there is.
using ColumnSumReduction = std::function<void(Eigen::ArrayXd& column_sums)>;

struct PcgOutcome {
    int iterations = 0;
    double relative_residual = 0;  // max over columns of |b - A x| / |b| (recurrence residual), for logs
    double error_bound = 0;        // the last value of the error bound
    bool converged = false;        // error_bound <= allowed_error
    bool cancelled = false;
};

// Solves A x = b for SPD A. `x` holds the initial guess on entry. Stops as soon as
// `error_bound` is at most `allowed_error`, or after `max_iterations`.
PcgOutcome block_pcg(const BlockOperator& apply_matrix, const BlockOperator& apply_preconditioner,
                     const Eigen::MatrixXd& b, Eigen::MatrixXd& x, const ErrorBound& error_bound, double allowed_error,
                     int max_iterations, const IterationObserver& observer = {},
                     const ColumnSumReduction& reduce_over_parts = {});

} // namespace geofilter
