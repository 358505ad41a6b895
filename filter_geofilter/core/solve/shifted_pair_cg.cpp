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

ShiftedTerm pair_term(std::complex<double> r) { return {r, Complex(0, -1 / r.imag())}; }

std::vector<ShiftedTerm> shifted_terms(const PartialFractions& g) {
    std::vector<ShiftedTerm> terms;
    for (size_t m = 0; m < g.poles.size(); ++m) {
        const Complex pole = g.poles[m], residue = g.residues[m];
        if (pole.imag() < 0) continue;  // with its conjugate
        terms.push_back({pole, pole.imag() > 0 ? 2.0 * residue : residue});
    }
    return terms;
}

PcgOutcome sum_shifted_solves(const BlockOperator& solve_shifted, double shift, const std::vector<ShiftedTerm>& terms,
                              const Eigen::MatrixXd& y, Eigen::MatrixXd& x, double allowed_error, int max_iterations,
                              const IterationObserver& observer, const ColumnSumReduction& reduce_over_parts) {
    const Eigen::Index rows = y.rows(), columns = y.cols();
    const auto column_sums = [&](Eigen::ArrayXd sums) {
        if (reduce_over_parts) reduce_over_parts(sums);
        return sums;
    };
    Eigen::MatrixXd residual, q;
    solve_shifted(y, residual);  // the seed's residual T y - T u at u = 0
    Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(rows, columns);

    // Each pole's shifted system is (T + s) w = T y with s = -1 / sigma, and z = s w: its
    // directions carry that factor already, so that their sum is z itself.
    struct Shifted {
        Complex s, weight;
        double bound_per_residual;
        Eigen::ArrayXcd zeta, zeta_previous, zeta_next;
        Eigen::MatrixXd direction_re, direction_im;
    };
    std::vector<Shifted> shifted;
    for (const ShiftedTerm& term : terms) {
        const Complex sigma = term.pole + shift;
        if (std::abs(sigma) <= 1e-14 * shift) {  // the real pole -shift: T y, exact
            sum += term.weight.real() * residual;
            continue;
        }
        Shifted t;
        t.s = -1.0 / sigma;
        t.weight = term.weight;
        t.bound_per_residual = std::abs(term.weight) / segment_distance_to_zero(sigma, shift);
        t.zeta = t.zeta_previous = Eigen::ArrayXcd::Ones(columns);
        t.zeta_next = Eigen::ArrayXcd::Zero(columns);
        t.direction_re = t.s.real() * residual;
        t.direction_im = t.s.imag() * residual;
        shifted.push_back(std::move(t));
    }
    Eigen::MatrixXd p = residual;
    Eigen::ArrayXd rr = column_sums(residual.colwise().squaredNorm().transpose().array());
    const Eigen::ArrayXd rr_start = rr;
    Eigen::ArrayXd alpha_previous = Eigen::ArrayXd::Ones(columns), beta_previous = Eigen::ArrayXd::Zero(columns);

    PcgOutcome outcome;
    const auto measure = [&] {
        double squared = 0, relative = 0;
        for (Eigen::Index c = 0; c < columns; ++c) {
            double column = 0, largest_zeta = 0;
            for (const Shifted& t : shifted) {
                column += t.bound_per_residual * std::abs(t.zeta[c]);
                largest_zeta = std::max(largest_zeta, std::abs(t.zeta[c]));
            }
            squared += column * column * rr[c];
            if (rr_start[c] > 0) relative = std::max(relative, largest_zeta * std::sqrt(rr[c] / rr_start[c]));
        }
        outcome.error_bound = std::sqrt(squared);
        outcome.relative_residual = relative;
        outcome.converged = outcome.error_bound <= allowed_error;
    };
    measure();
    for (int it = 1; !outcome.converged && it <= max_iterations; ++it) {
        if (!std::isfinite(outcome.error_bound)) return outcome;
        solve_shifted(p, q);
        const Eigen::ArrayXd pq = column_sums(p.cwiseProduct(q).colwise().sum().transpose().array());
        Eigen::ArrayXd alpha = Eigen::ArrayXd::Zero(columns);
        for (Eigen::Index c = 0; c < columns; ++c) {
            // A column whose seed has converged exactly has nothing left to add.
            if (rr[c] == 0 || !(pq[c] > 0)) continue;
            alpha[c] = rr[c] / pq[c];
            for (Shifted& t : shifted) {
                // zeta_k = 1 / R_k(-s), R_k the seed's residual polynomial, by its three-term recurrence.
                const Complex zeta = t.zeta[c], zeta_previous = t.zeta_previous[c];
                t.zeta_next[c] = zeta * zeta_previous * alpha_previous[c] /
                                 (alpha[c] * beta_previous[c] * (zeta_previous - zeta) +
                                  zeta_previous * alpha_previous[c] * (1.0 + t.s * alpha[c]));
                const Complex step = t.weight * alpha[c] * t.zeta_next[c] / zeta;
                sum.col(c) += step.real() * t.direction_re.col(c) - step.imag() * t.direction_im.col(c);
            }
            residual.col(c) -= alpha[c] * q.col(c);
        }
        const Eigen::ArrayXd rr_next = column_sums(residual.colwise().squaredNorm().transpose().array());
        for (Eigen::Index c = 0; c < columns; ++c) {
            if (alpha[c] == 0) {
                rr[c] = 0;
                continue;
            }
            const double beta = rr_next[c] / rr[c];
            const double* res = residual.col(c).data();
            for (Shifted& t : shifted) {
                const Complex ratio = t.zeta_next[c] / t.zeta[c];
                const Complex beta_shifted = ratio * ratio * beta;
                const Complex lead = t.zeta_next[c] * t.s;
                double* re = t.direction_re.col(c).data();
                double* im = t.direction_im.col(c).data();
                for (Eigen::Index i = 0; i < rows; ++i) {
                    const double old_re = re[i];
                    re[i] = lead.real() * res[i] + beta_shifted.real() * old_re - beta_shifted.imag() * im[i];
                    im[i] = lead.imag() * res[i] + beta_shifted.real() * im[i] + beta_shifted.imag() * old_re;
                }
                t.zeta_previous[c] = t.zeta[c];
                t.zeta[c] = t.zeta_next[c];
            }
            p.col(c) = residual.col(c) + beta * p.col(c);
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
    if (outcome.converged) x += sum;
    return outcome;
}

} // namespace geofilter::detail
