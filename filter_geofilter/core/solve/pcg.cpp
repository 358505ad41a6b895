#include "core/solve/pcg.h"

#include <cmath>

namespace geofilter {

PcgOutcome block_pcg(const BlockOperator& apply_matrix, const BlockOperator& apply_preconditioner,
                     const Eigen::MatrixXd& b, Eigen::MatrixXd& x, const ErrorBound& error_bound, double allowed_error,
                     int max_iterations, const IterationObserver& observer,
                     const ColumnSumReduction& reduce_over_parts) {
    const Eigen::Index columns = b.cols();
    Eigen::MatrixXd r(b.rows(), columns), z(b.rows(), columns), p, q(b.rows(), columns);
    apply_matrix(x, q);
    r = b - q;
    auto dot_columns = [&](const Eigen::MatrixXd& u, const Eigen::MatrixXd& v) -> Eigen::ArrayXd {
        Eigen::ArrayXd sums = u.cwiseProduct(v).colwise().sum().transpose().array();
        if (reduce_over_parts) reduce_over_parts(sums);
        return sums;
    };
    const Eigen::ArrayXd b_norm = dot_columns(b, b).sqrt();
    auto worst_residual = [&]() {
        const Eigen::ArrayXd r_norm = dot_columns(r, r).sqrt();
        double worst = 0;
        for (Eigen::Index c = 0; c < columns; ++c) worst = std::max(worst, b_norm[c] > 0 ? r_norm[c] / b_norm[c] : r_norm[c]);
        return worst;
    };

    PcgOutcome outcome;
    outcome.relative_residual = worst_residual();
    apply_preconditioner(r, z);
    Eigen::ArrayXd rz = dot_columns(r, z);
    outcome.error_bound = error_bound(r, rz);
    if (outcome.error_bound <= allowed_error) {
        outcome.converged = true;
        return outcome;
    }
    p = z;
    for (int it = 1; it <= max_iterations; ++it) {
        apply_matrix(p, q);
        const Eigen::ArrayXd pq = dot_columns(p, q);
        for (Eigen::Index c = 0; c < columns; ++c) {
            // A column that has converged exactly has rz = 0: leave it alone.
            const double alpha = (pq[c] > 0 && rz[c] != 0) ? rz[c] / pq[c] : 0.0;
            x.col(c) += alpha * p.col(c);
            r.col(c) -= alpha * q.col(c);
        }
        outcome.iterations = it;
        outcome.relative_residual = worst_residual();
        if (!std::isfinite(outcome.relative_residual)) return outcome;
        apply_preconditioner(r, z);
        const Eigen::ArrayXd rz_next = dot_columns(r, z);
        outcome.error_bound = error_bound(r, rz_next);
        if (outcome.error_bound <= allowed_error) {
            outcome.converged = true;
            return outcome;
        }
        if (observer && (it % 16 == 0) && !observer(it, outcome.error_bound)) {
            outcome.cancelled = true;
            return outcome;
        }
        for (Eigen::Index c = 0; c < columns; ++c) {
            const double beta = rz[c] != 0 ? rz_next[c] / rz[c] : 0.0;
            p.col(c) = z.col(c) + beta * p.col(c);
        }
        rz = rz_next;
    }
    return outcome;
}

} // namespace geofilter
