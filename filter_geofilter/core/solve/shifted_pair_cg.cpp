#include "core/solve/shifted_pair_cg.h"

#include <algorithm>
#include <cmath>

namespace geofilter::detail {

namespace {

using Complex = std::complex<double>;

// min over 0 <= mu <= 1 / shift of |1 - sigma mu|.
double segment_distance_to_zero(Complex sigma, double shift) {
    const double mu = std::clamp(sigma.real() / std::norm(sigma), 0.0, 1 / shift);
    return std::abs(1.0 - sigma * mu);
}

} // namespace

double shifted_pair_rate(std::complex<double> r, double shift) {
    const Complex w = 1.0 - 2 * shift / (r + shift);
    const Complex root = std::sqrt(w * w - 1.0);
    return 1 / std::max(std::abs(w + root), std::abs(w - root));
}

double shifted_pair_iterations(std::complex<double> r, double shift, int last_iterations, double last_rate) {
    const double rate = shifted_pair_rate(r, shift);
    if (last_iterations > 0 && last_rate > 0 && last_rate < 1) return last_iterations * std::log(last_rate) / std::log(rate);
    return 13 * (1 + rate * rate) / (1 - rate * rate);
}

PcgOutcome solve_pair_by_shifted_cg(const BlockOperator& solve_shifted, double shift, std::complex<double> r,
                                    const Eigen::MatrixXd& y, Eigen::MatrixXd& x, double allowed_error,
                                    int max_iterations, const IterationObserver& observer) {
    const Eigen::Index rows = y.rows(), columns = y.cols();
    const Complex sigma = r + shift;
    // The shifted system is (T + s) w = T y with z = -w / sigma; the directions below carry
    // that factor already, so that their sum is z itself.
    const Complex s = -1.0 / sigma, scale = -1.0 / sigma;
    const double bound_per_residual = 1 / (segment_distance_to_zero(sigma, shift) * std::abs(r.imag()));

    Eigen::MatrixXd residual, q;
    solve_shifted(y, residual);  // the seed's residual T y - T u at u = 0
    Eigen::MatrixXd p = residual;
    Eigen::MatrixXd direction_re = scale.real() * residual, direction_im = scale.imag() * residual;
    Eigen::MatrixXd z_im = Eigen::MatrixXd::Zero(rows, columns);

    Eigen::ArrayXd rr = residual.colwise().squaredNorm().transpose().array();
    const Eigen::ArrayXd rr_start = rr;
    Eigen::ArrayXcd zeta = Eigen::ArrayXcd::Ones(columns), zeta_previous = zeta;
    Eigen::ArrayXd alpha_previous = Eigen::ArrayXd::Ones(columns), beta_previous = Eigen::ArrayXd::Zero(columns);
    Eigen::ArrayXcd zeta_next(columns);

    PcgOutcome outcome;
    const auto measure = [&] {
        double squared = 0, relative = 0;
        for (Eigen::Index c = 0; c < columns; ++c) {
            squared += std::norm(zeta[c]) * rr[c];
            if (rr_start[c] > 0) relative = std::max(relative, std::abs(zeta[c]) * std::sqrt(rr[c] / rr_start[c]));
        }
        outcome.error_bound = std::sqrt(squared) * bound_per_residual;
        outcome.relative_residual = relative;
        outcome.converged = outcome.error_bound <= allowed_error;
    };
    measure();
    for (int it = 1; !outcome.converged && it <= max_iterations; ++it) {
        if (!std::isfinite(outcome.error_bound)) return outcome;
        solve_shifted(p, q);
        const Eigen::ArrayXd pq = p.cwiseProduct(q).colwise().sum().transpose().array();
        Eigen::ArrayXd alpha = Eigen::ArrayXd::Zero(columns);
        for (Eigen::Index c = 0; c < columns; ++c) {
            // A column whose seed has converged exactly has nothing left to add.
            if (rr[c] == 0 || !(pq[c] > 0)) {
                zeta_next[c] = 0;
                continue;
            }
            alpha[c] = rr[c] / pq[c];
            // zeta_k = 1 / R_k(-s), R_k the seed's residual polynomial, by its three-term recurrence.
            zeta_next[c] = zeta[c] * zeta_previous[c] * alpha_previous[c] /
                           (alpha[c] * beta_previous[c] * (zeta_previous[c] - zeta[c]) +
                            zeta_previous[c] * alpha_previous[c] * (1.0 + s * alpha[c]));
            const Complex step = alpha[c] * zeta_next[c] / zeta[c];
            z_im.col(c) += step.real() * direction_im.col(c) + step.imag() * direction_re.col(c);
            residual.col(c) -= alpha[c] * q.col(c);
        }
        const Eigen::ArrayXd rr_next = residual.colwise().squaredNorm().transpose().array();
        for (Eigen::Index c = 0; c < columns; ++c) {
            if (alpha[c] == 0) {
                rr[c] = 0;
                zeta[c] = 0;
                continue;
            }
            const double beta = rr_next[c] / rr[c];
            const Complex ratio = zeta_next[c] / zeta[c];
            const Complex beta_shifted = ratio * ratio * beta;
            const Complex lead = zeta_next[c] * scale;
            double* re = direction_re.col(c).data();
            double* im = direction_im.col(c).data();
            const double* res = residual.col(c).data();
            for (Eigen::Index i = 0; i < rows; ++i) {
                const double old_re = re[i];
                re[i] = lead.real() * res[i] + beta_shifted.real() * old_re - beta_shifted.imag() * im[i];
                im[i] = lead.imag() * res[i] + beta_shifted.real() * im[i] + beta_shifted.imag() * old_re;
            }
            p.col(c) = residual.col(c) + beta * p.col(c);
            zeta_previous[c] = zeta[c];
            zeta[c] = zeta_next[c];
            alpha_previous[c] = alpha[c];
            beta_previous[c] = beta;
            rr[c] = rr_next[c];
        }
        outcome.iterations = it;
        measure();
        if (!outcome.converged && observer && it % 16 == 0 && !observer(it, outcome.error_bound)) {
            outcome.cancelled = true;
            return outcome;
        }
    }
    if (outcome.converged) x += z_im / r.imag();
    return outcome;
}

} // namespace geofilter::detail
