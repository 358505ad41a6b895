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
    // The columns' processes are independent but advance together: one product with K per
    // step for all of them, which reads K once instead of once per column. (Sharing each
    // product's rows out among two threads was measured slower at 384k vertices.)
    const auto apply_a = [&](const Eigen::MatrixXd& x, Eigen::MatrixXd& out) {
        out.noalias() = k.transpose() * x;  // K is symmetric: row by row, gathering
        out = inverse_mass.asDiagonal() * out;
    };
    const auto mass_dot = [&](const Eigen::MatrixXd& x, const Eigen::MatrixXd& y, Eigen::Index c) {
        return (mass.array() * x.col(c).array() * y.col(c).array()).sum();
    };
    const Eigen::Index columns = values.cols();
    // Each column's share of the Frobenius budget.
    const double allowed_per_column = allowed_error / std::sqrt(static_cast<double>(std::max<Eigen::Index>(columns, 1)));

    Eigen::MatrixXd out = values;
    KrylovReport r;
    Eigen::MatrixXd start;
    apply_a(values, start);
    std::vector<double> start_norm(static_cast<std::size_t>(columns));
    // A column in the kernel of A (G(A) b = b) or whose process has ended takes no more steps.
    std::vector<bool> running(static_cast<std::size_t>(columns));
    for (Eigen::Index c = 0; c < columns; ++c) {
        start_norm[c] = std::sqrt(mass_dot(start, start, c));
        running[c] = start_norm[c] > 0;
    }
    // The Lanczos recurrence; `step` advances the running columns by one, recording alpha and
    // beta on the first pass and replaying them on the second.
    std::vector<std::vector<double>> alpha(static_cast<std::size_t>(columns)), beta(alpha);
    Eigen::MatrixXd previous, current, w;
    const auto restart = [&] {
        previous = Eigen::MatrixXd::Zero(start.rows(), columns);
        current = start;
        for (Eigen::Index c = 0; c < columns; ++c)
            if (start_norm[c] > 0) current.col(c) /= start_norm[c];
    };
    const auto step = [&](std::size_t j, bool record, const std::vector<bool>& moving) {
        apply_a(current, w);
        for (Eigen::Index c = 0; c < columns; ++c) {
            if (!moving[c]) continue;
            const double a = record ? mass_dot(w, current, c) : alpha[c][j];
            w.col(c) -= a * current.col(c);
            if (j > 0) w.col(c) -= beta[c][j - 1] * previous.col(c);
            const double b = record ? std::sqrt(mass_dot(w, w, c)) : beta[c][j];
            if (record) {
                alpha[c].push_back(a);
                beta[c].push_back(b);
            }
            previous.col(c) = current.col(c);
            if (b > 0) current.col(c) = w.col(c) / b;
        }
    };

    restart();
    std::vector<TridiagonalQuotient> quotient(static_cast<std::size_t>(columns));
    std::vector<double> bound(static_cast<std::size_t>(columns), 0.0);
    std::vector<int> steps(static_cast<std::size_t>(columns), 0);
    for (int taken = 0; std::find(running.begin(), running.end(), true) != running.end();) {
        step(static_cast<std::size_t>(taken), true, running);
        ++taken;
        for (Eigen::Index c = 0; c < columns; ++c) {
            if (!running[c]) continue;
            steps[c] = taken;
            if (taken % 4 == 0 || beta[c].back() == 0 || taken == max_steps) {
                const std::vector<double> off(beta[c].begin(), beta[c].end() - 1);
                quotient[c] = highpass_quotient_of_tridiagonal(alpha[c], off, q);
                bound[c] = start_norm[c] * beta[c].back() * quotient[c].error_factor;
                if (bound[c] <= allowed_per_column) {
                    running[c] = false;
                } else if (taken >= max_steps) {
                    r.converged = false;
                    r.iterations = taken;
                    r.error_bound = bound[c];
                    if (report) *report = r;
                    return values;
                }
            }
        }
    }
    // The same bases again, each column summed with its coefficients.
    restart();
    Eigen::MatrixXd removed = Eigen::MatrixXd::Zero(start.rows(), columns);
    const int most = *std::max_element(steps.begin(), steps.end());
    std::vector<bool> moving(static_cast<std::size_t>(columns));
    for (int j = 0; j < most; ++j) {
        for (Eigen::Index c = 0; c < columns; ++c) {
            if (j < steps[c]) removed.col(c) += quotient[c].coefficients[j] * current.col(c);
            moving[c] = j + 1 < steps[c];
        }
        if (j + 1 < most) step(static_cast<std::size_t>(j), false, moving);
    }
    double squared_bound = 0;
    for (Eigen::Index c = 0; c < columns; ++c) {
        if (!(start_norm[c] > 0)) continue;
        out.col(c) -= start_norm[c] * removed.col(c);
        r.iterations = std::max(r.iterations, steps[c]);
        squared_bound += bound[c] * bound[c];
    }
    r.error_bound = std::sqrt(squared_bound);
    if (report) *report = r;
    return out;
}

} // namespace geofilter
