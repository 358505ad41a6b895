#include "core/solve/krylov_lowpass.h"

#include "core/types.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

namespace geofilter {

namespace {

using Complex = std::complex<double>;

// q(s) = (1 - G(s)) / s = sum_m w_m / (s - p_m): G(s) = G(inf) + sum_m rho_m / (s - p_m) with
// rho_m = gain N(p_m) / prod_{j != m} (p_m - p_j), and G(0) = 1 cancels q's 1/s term, so
// w_m = -rho_m / p_m.
struct PartialFractions {
    std::vector<Complex> poles, weights;
};

// G qualifies (krylov_lowpass_applies).
PartialFractions partial_fractions_of_highpass_quotient(const TransferFunction& g) {
    PartialFractions out;
    for (std::size_t m = 0; m < g.poles.size(); ++m) {
        const Complex p = g.poles[m];
        Complex residue = g.gain;
        for (const auto& factor : g.numerator) {
            Complex value = 0;
            for (auto c = factor.rbegin(); c != factor.rend(); ++c) value = value * p + *c;
            residue *= value;
        }
        for (std::size_t j = 0; j < g.poles.size(); ++j)
            if (j != m) residue /= p - g.poles[j];
        out.poles.push_back(p);
        out.weights.push_back(-residue / p);
    }
    return out;
}

// q(T) e1 for the symmetric tridiagonal T (diagonal alpha, off-diagonal beta), one
// elimination per pole: the pivots d_j = alpha_j - p - beta^2 / d_(j-1) keep an imaginary
// part of at least |Im p| (a real pole is negative and T's eigenvalues are not). Also
// sum_m |w_m| |e_k^T (T - p_m)^-1 e1| / dist(p_m, [0, inf)): times the norm of the start
// vector and the next off-diagonal entry, a bound on the error in the mass norm. The
// process solved each (A - p_m) x = r by the Galerkin condition, whose residual is that last
// entry times beta_k v_(k+1); (A - p_m)^-1 has norm at most 1 / dist(p_m, [0, inf)) there.
struct TridiagonalQuotient {
    Eigen::VectorXd coefficients;
    double error_factor = 0;
};

TridiagonalQuotient highpass_quotient_of_tridiagonal(const std::vector<double>& alpha, const std::vector<double>& beta,
                                                     const PartialFractions& q) {
    const std::size_t k = alpha.size();
    TridiagonalQuotient out;
    out.coefficients = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(k));
    std::vector<Complex> pivot(k), right(k);
    for (std::size_t m = 0; m < q.poles.size(); ++m) {
        const Complex p = q.poles[m];
        // Forward elimination of (T - p I) x = e1, then back substitution.
        pivot[0] = alpha[0] - p;
        right[0] = 1;
        for (std::size_t j = 1; j < k; ++j) {
            const Complex factor = beta[j - 1] / pivot[j - 1];
            pivot[j] = alpha[j] - p - factor * beta[j - 1];
            right[j] = -factor * right[j - 1];
        }
        Complex next = right[k - 1] / pivot[k - 1];
        const double distance = p.real() <= 0 ? std::abs(p) : std::abs(p.imag());
        out.error_factor += std::abs(q.weights[m]) * std::abs(next) / distance;
        out.coefficients[static_cast<Eigen::Index>(k - 1)] += (q.weights[m] * next).real();
        for (std::size_t j = k - 1; j-- > 0;) {
            next = (right[j] - beta[j] * next) / pivot[j];
            out.coefficients[static_cast<Eigen::Index>(j)] += (q.weights[m] * next).real();
        }
    }
    return out;
}

} // namespace

bool krylov_lowpass_applies(const TransferFunction& g) {
    if (g.poles.empty() || std::abs(g(0) - 1) > 1e-12 || !std::isfinite(g.at_infinity())) return false;
    for (std::size_t i = 0; i < g.poles.size(); ++i) {
        if (g.poles[i].imag() == 0 && g.poles[i].real() >= 0) return false;
        for (std::size_t j = 0; j < i; ++j)
            if (std::abs(g.poles[i] - g.poles[j]) <= 1e-9 * std::abs(g.poles[i])) return false;
    }
    return true;
}

Eigen::MatrixXd krylov_lowpass(const Laplacian& laplacian, const Eigen::MatrixXd& values, const TransferFunction& g,
                               double allowed_error, int max_steps, KrylovReport* report) {
    if (!(allowed_error > 0)) throw Error("a Krylov lowpass needs a positive allowed error (got " + format_number(allowed_error) + ")");
    if (!krylov_lowpass_applies(g))
        throw Error("a Krylov lowpass needs G(0) = 1, G finite at infinity, and simple poles off s >= 0 (at least one)");
    const PartialFractions q = partial_fractions_of_highpass_quotient(g);
    const SparseMatrix& k = laplacian.stiffness;
    const Eigen::VectorXd& mass = laplacian.mass;
    Eigen::VectorXd inverse_mass = Eigen::VectorXd::Zero(mass.size());
    for (Eigen::Index i = 0; i < mass.size(); ++i)
        if (mass[i] > 0) inverse_mass[i] = 1 / mass[i];
    const auto apply_a = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return inverse_mass.asDiagonal() * (k * x); };
    const auto mass_dot = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& y) { return (mass.array() * x.array() * y.array()).sum(); };
    // Each column's share of the Frobenius budget.
    const double allowed_per_column = allowed_error / std::sqrt(static_cast<double>(std::max<Eigen::Index>(values.cols(), 1)));

    Eigen::MatrixXd out = values;
    KrylovReport r;
    double squared_bound = 0;
    for (Eigen::Index column = 0; column < values.cols(); ++column) {
        const Eigen::VectorXd start = apply_a(values.col(column));
        const double start_norm = std::sqrt(mass_dot(start, start));
        if (!(start_norm > 0)) continue;  // in the kernel of A: G(A) b = b

        // The Lanczos recurrence; `step` advances it by one, recording alpha and beta on the
        // first pass and replaying them on the second.
        std::vector<double> alpha, beta;
        Eigen::VectorXd previous, current;
        const auto restart = [&] {
            previous = Eigen::VectorXd::Zero(start.size());
            current = start / start_norm;
        };
        const auto step = [&](std::size_t j, bool record) {
            Eigen::VectorXd w = apply_a(current);
            const double a = record ? mass_dot(w, current) : alpha[j];
            w -= a * current;
            if (j > 0) w -= beta[j - 1] * previous;
            const double b = record ? std::sqrt(mass_dot(w, w)) : beta[j];
            if (record) {
                alpha.push_back(a);
                beta.push_back(b);
            }
            previous.swap(current);
            if (b > 0) current = w / b;
        };

        restart();
        TridiagonalQuotient quotient;
        double bound = INFINITY;
        int steps = 0;
        while (true) {
            step(static_cast<std::size_t>(steps), true);
            ++steps;
            if (steps % 4 == 0 || beta.back() == 0 || steps == max_steps) {
                const std::vector<double> off(beta.begin(), beta.end() - 1);
                quotient = highpass_quotient_of_tridiagonal(alpha, off, q);
                bound = start_norm * beta.back() * quotient.error_factor;
                if (bound <= allowed_per_column) break;
                if (steps >= max_steps) {
                    r.converged = false;
                    r.iterations = steps;
                    r.error_bound = bound;
                    if (report) *report = r;
                    return values;
                }
            }
        }
        // The same basis again, summed with the coefficients.
        restart();
        Eigen::VectorXd removed = Eigen::VectorXd::Zero(start.size());
        for (int j = 0; j < steps; ++j) {
            removed += quotient.coefficients[j] * current;
            if (j + 1 < steps) step(static_cast<std::size_t>(j), false);
        }
        out.col(column) -= start_norm * removed;
        r.iterations = std::max(r.iterations, steps);
        squared_bound += bound * bound;
    }
    r.error_bound = std::sqrt(squared_bound);
    if (report) *report = r;
    return out;
}

} // namespace geofilter
