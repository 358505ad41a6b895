#include "pcg.h"

#include <cmath>

namespace geofilter {

PcgOutcome block_pcg(const BlockOperator& apply_matrix, const BlockOperator& apply_preconditioner,
                     const Eigen::MatrixXd& b, Eigen::MatrixXd& x, double tolerance, int max_iterations,
                     const IterationObserver& observer, const StepTest& step_small) {
    const Eigen::Index columns = b.cols();
    Eigen::MatrixXd r(b.rows(), columns), z(b.rows(), columns), p, q(b.rows(), columns);
    apply_matrix(x, q);
    r = b - q;
    const Eigen::ArrayXd b_norm = b.colwise().norm().transpose().array();
    auto worst_residual = [&]() {
        double worst = 0;
        for (Eigen::Index c = 0; c < columns; ++c) {
            const double rel = b_norm[c] > 0 ? r.col(c).norm() / b_norm[c] : r.col(c).norm();
            worst = std::max(worst, rel);
        }
        return worst;
    };

    PcgOutcome outcome;
    outcome.relative_residual = worst_residual();
    if (outcome.relative_residual <= tolerance) {
        outcome.converged = true;
        return outcome;
    }
    apply_preconditioner(r, z);
    p = z;
    Eigen::ArrayXd rz = (r.cwiseProduct(z)).colwise().sum().transpose().array();

    Eigen::MatrixXd step;
    int small_steps = 0;
    for (int it = 1; it <= max_iterations; ++it) {
        apply_matrix(p, q);
        const Eigen::ArrayXd pq = (p.cwiseProduct(q)).colwise().sum().transpose().array();
        Eigen::ArrayXd alpha(columns);
        for (Eigen::Index c = 0; c < columns; ++c) {
            // A column that has converged exactly has rz = 0: leave it alone.
            alpha[c] = (pq[c] > 0 && rz[c] != 0) ? rz[c] / pq[c] : 0.0;
            x.col(c) += alpha[c] * p.col(c);
            r.col(c) -= alpha[c] * q.col(c);
        }
        outcome.iterations = it;
        outcome.relative_residual = worst_residual();
        if (!std::isfinite(outcome.relative_residual)) return outcome;
        if (step_small) {
            step = p * alpha.matrix().asDiagonal();
            small_steps = step_small(step) ? small_steps + 1 : 0;
        }
        if (outcome.relative_residual <= tolerance || small_steps >= 2) {
            outcome.converged = true;
            outcome.converged_by_step = outcome.relative_residual > tolerance;
            return outcome;
        }
        if (observer && (it % 16 == 0) && !observer(it, outcome.relative_residual)) {
            outcome.cancelled = true;
            return outcome;
        }
        apply_preconditioner(r, z);
        const Eigen::ArrayXd rz_next = (r.cwiseProduct(z)).colwise().sum().transpose().array();
        for (Eigen::Index c = 0; c < columns; ++c) {
            const double beta = rz[c] != 0 ? rz_next[c] / rz[c] : 0.0;
            p.col(c) = z.col(c) + beta * p.col(c);
        }
        rz = rz_next;
    }
    return outcome;
}

} // namespace geofilter
