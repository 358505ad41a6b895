// The fast solver. In the frame q = M^1/2 p the operator is the symmetric
// Kt = M^-1/2 K M^-1/2 and the filter is the matrix function G(Kt): a polynomial
// numerator times one solve per pole. All factors are polynomials in the same Kt, so
// they commute and can be applied in any order, and every shifted matrix Kt + c I has
// the same sparsity: CHOLMOD's symbolic analysis is done once per mesh.
#include "pcg.h"
#include "solvers.h"

#include <Eigen/CholmodSupport>

#include <chrono>
#include <cmath>
#include <complex>

namespace geofilter::detail {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Horner: c_n Kt^n y + ... + c_0 y.
Eigen::MatrixXd apply_polynomial(const SparseMatrix& kt, const std::vector<double>& c, const Eigen::MatrixXd& y) {
    Eigen::MatrixXd acc = c.back() * y;
    for (int k = static_cast<int>(c.size()) - 2; k >= 0; --k) {
        Eigen::MatrixXd next = kt * acc;
        next += c[k] * y;
        acc.swap(next);
    }
    return acc;
}

class ShiftedCholesky {
public:
    explicit ShiftedCholesky(const SparseMatrix& kt) : kt_(kt) { llt_.analyzePattern(kt_); }

    // Factorises Kt + shift I unless that factor is already held.
    void factorize(double shift) {
        if (shift == shift_) return;
        llt_.setShift(shift);
        llt_.factorize(kt_);
        if (llt_.info() != Eigen::Success)
            throw Error("the sparse Cholesky factorisation failed (Kt + " + std::to_string(shift) +
                        " I is not positive definite): the mesh has inverted or degenerate faces");
        shift_ = shift;
    }
    Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const { return llt_.solve(b); }

private:
    const SparseMatrix& kt_;
    Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt_;
    double shift_ = NAN;
};

} // namespace

Eigen::MatrixXd solve_factored(const FilterProblem& problem, FilterReport& report) {
    const TransferFunction& g = problem.g;
    const Eigen::VectorXd sqrt_mass = problem.laplacian.mass.cwiseSqrt();
    const SparseMatrix kt = mass_normalized_stiffness(problem.laplacian);
    Eigen::MatrixXd y = sqrt_mass.asDiagonal() * problem.coordinates;

    report_progress(problem.options, 0.05, "analysing the sparsity pattern");
    auto t = std::chrono::steady_clock::now();
    ShiftedCholesky cholesky(kt);
    report.seconds_factorization += seconds_since(t);

    const size_t pole_count = g.poles.size();
    size_t next_pole = 0, next_numerator = 0;
    while (next_pole < pole_count || next_numerator < g.numerator.size()) {
        if (next_numerator < g.numerator.size()) {
            t = std::chrono::steady_clock::now();
            y = apply_polynomial(kt, g.numerator[next_numerator++], y);
            report.seconds_solve += seconds_since(t);
        }
        if (next_pole >= pole_count) continue;
        const std::complex<double> pole = g.poles[next_pole];
        const bool pair = pole.imag() != 0;
        next_pole += pair ? 2 : 1;
        const double done = static_cast<double>(next_pole) / static_cast<double>(pole_count);

        if (!pair) {
            if (pole.real() >= 0) throw Error("unstable filter: a pole lies at s = " + std::to_string(pole.real()) + " >= 0");
            report_progress(problem.options, 0.1 + 0.8 * done - 0.4 / pole_count, "factorising");
            t = std::chrono::steady_clock::now();
            cholesky.factorize(-pole.real());
            report.seconds_factorization += seconds_since(t);
            t = std::chrono::steady_clock::now();
            Eigen::MatrixXd solved = cholesky.solve(y);
            const Eigen::MatrixXd residual = kt * solved - pole.real() * solved - y;
            report.relative_residual = std::max(report.relative_residual, residual.norm() / std::max(y.norm(), 1e-300));
            y.swap(solved);
            report.seconds_solve += seconds_since(t);
            continue;
        }

        // A complex pair r, conj(r): solve (Kt - r)(Kt - conj r) x = y with CG, preconditioned by
        // (Kt + |r|)^2. Per eigenvalue l >= 0 the ratio |l - r|^2 / (l + |r|)^2 lies in
        // [sin^2(arg(r)/2), 1], so the condition number is at most 1 / sin^2(arg(r)/2).
        const double modulus = std::abs(pole), twice_re = 2 * pole.real(), modulus2 = std::norm(pole);
        report_progress(problem.options, 0.1 + 0.8 * done - 0.4 / pole_count, "factorising");
        t = std::chrono::steady_clock::now();
        cholesky.factorize(modulus);
        report.seconds_factorization += seconds_since(t);
        t = std::chrono::steady_clock::now();
        const BlockOperator quadratic = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
            const Eigen::MatrixXd k_in = kt * in;
            out = kt * k_in;
            out -= twice_re * k_in;
            out += modulus2 * in;
        };
        const BlockOperator preconditioner = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
            out = cholesky.solve(cholesky.solve(in));
        };
        Eigen::MatrixXd x = Eigen::MatrixXd::Zero(y.rows(), y.cols());
        const PcgOutcome outcome = block_pcg(quadratic, preconditioner, y, x, problem.options.tolerance,
                                             problem.options.max_iterations, [&](int, double) {
                                                 return !problem.options.progress || problem.options.progress(0.1 + 0.8 * done - 0.2 / pole_count, "solving");
                                             });
        report.iterations += outcome.iterations;
        report.relative_residual = std::max(report.relative_residual, outcome.relative_residual);
        if (outcome.cancelled) throw Error("cancelled by the user");
        if (!outcome.converged)
            throw Error("the solver did not converge in " + std::to_string(outcome.iterations) +
                        " iterations (relative residual " + std::to_string(outcome.relative_residual) +
                        "); raise the iteration cap or the tolerance");
        y.swap(x);
        report.seconds_solve += seconds_since(t);
    }
    y *= g.gain;
    return sqrt_mass.cwiseInverse().asDiagonal() * y;
}

} // namespace geofilter::detail
