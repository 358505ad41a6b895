// The paper's solver (section 2.4): Jacobi-preconditioned CG on eq. 9, matrix-free.
// It runs in the frame q = M^1/2 p, where eq. 9 becomes D(Kt) q' = N(Kt) q with
// Kt = M^-1/2 K M^-1/2. Jacobi preconditioning is invariant under that diagonal
// similarity, so the iterates are the paper's. Its cost grows as s1 falls (the condition
// number is ~ a2 lambda_max^2 / a0): kept as the reference the fast solver is checked against.
#include "core/solve/cascade.h"
#include "core/solve/pcg.h"
#include "core/solve/solvers.h"

#include <algorithm>

#include <chrono>
#include <cmath>

namespace geofilter::detail {

namespace {

// Column sums of squares of a symmetric matrix = diagonal of its square, in linear time.
Eigen::VectorXd diagonal_of_square(const SparseMatrix& a) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(a.cols());
    for (Eigen::Index col = 0; col < a.outerSize(); ++col)
        for (SparseMatrix::InnerIterator it(a, col); it; ++it) d[col] += it.value() * it.value();
    return d;
}

// min of c0 + c1 s + c2 s^2 over s >= 0 (c2 >= 0): a lower bound on the eigenvalues of
// c0 + c1 Kt + c2 Kt^2, since those are its values at Kt's eigenvalues.
double smallest_value_on_spectrum(double c0, double c1, double c2) {
    const double vertex = c2 > 0 ? -c1 / (2 * c2) : 0.0;
    return vertex > 0 ? c0 + vertex * (c1 + vertex * c2) : c0;
}

// Jacobi-PCG on (c0 + c1 Kt + c2 Kt^2) x = b, starting from x, until the error bound
// |residual| / lambda_min (lambda_min from smallest_value_on_spectrum) is below allowed_error.
class JacobiPcg : public PoleGroupSolver {
public:
    JacobiPcg(const FilterProblem& problem, FilterReport& report)
        : problem_(problem), report_(report), kt_(mass_normalized_stiffness(problem.laplacian)),
          kt_diagonal_(kt_.diagonal()), kt2_diagonal_(diagonal_of_square(kt_)) {}

    const SparseMatrix& kt() const { return kt_; }

    Eigen::MatrixXd polynomial(const std::vector<double>& c, const Eigen::MatrixXd& y) override {
        return apply_polynomial(kt_, c, y);
    }
    Eigen::MatrixXd real_pole(double r, const Eigen::MatrixXd& y, double allowed_error, double progress) override {
        Eigen::MatrixXd x = y;
        solve(-r, 1, 0, y, x, allowed_error, progress);
        return x;
    }
    Eigen::MatrixXd conjugate_pair(std::complex<double> r, const Eigen::MatrixXd& y, double allowed_error,
                                   double progress) override {
        Eigen::MatrixXd x = y;
        solve(std::norm(r), -2 * r.real(), 1, y, x, allowed_error, progress);
        return x;
    }

    void solve(double c0, double c1, double c2, const Eigen::MatrixXd& b, Eigen::MatrixXd& x, double allowed_error,
               double progress_base) {
        const BlockOperator matrix = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
            const Eigen::MatrixXd k_in = kt_ * in;
            out = c0 * in + c1 * k_in;
            if (c2 != 0) out += c2 * (kt_ * k_in);
        };
        const Eigen::VectorXd inverse_diagonal =
            (Eigen::VectorXd::Constant(kt_.rows(), c0) + c1 * kt_diagonal_ + c2 * kt2_diagonal_).cwiseInverse();
        const BlockOperator jacobi = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
            out = inverse_diagonal.asDiagonal() * in;
        };
        const double lambda_min = smallest_value_on_spectrum(c0, c1, c2);
        if (!(lambda_min > 0)) throw Error("unstable filter: its denominator is not positive on the spectrum");
        const ErrorBound bound = [&](const Eigen::MatrixXd& residual, const Eigen::ArrayXd&) {
            return residual.norm() / lambda_min;
        };
        const FilterOptions& options = problem_.options;
        double first_bound = 0;
        const PcgOutcome outcome = block_pcg(matrix, jacobi, b, x, bound, allowed_error, options.max_iterations,
                                             [&](int, double error_bound) {
            if (first_bound == 0) first_bound = error_bound;
            const double fraction = std::clamp(std::log(first_bound / error_bound) /
                                                   std::max(std::log(first_bound / allowed_error), 1e-300),
                                               0.0, 1.0);
            return !options.progress || options.progress(progress_base + 0.4 * fraction, "solving (Jacobi-PCG)");
        });
        record_pcg_outcome(outcome, allowed_error,
                           "raise maxIterations or the tolerance, or use the factored solver (the Jacobi-PCG is the"
                           " paper's reference, slow for wide features)",
                           report_);
    }

private:
    const FilterProblem& problem_;
    FilterReport& report_;
    SparseMatrix kt_;
    Eigen::VectorXd kt_diagonal_, kt2_diagonal_;
};

} // namespace

Eigen::MatrixXd solve_jacobi_pcg(const FilterProblem& problem, FilterReport& report) {
    const auto t0 = std::chrono::steady_clock::now();
    const TransferFunction& g = problem.g;
    const Eigen::VectorXd sqrt_mass = problem.laplacian.mass.cwiseSqrt();
    JacobiPcg pcg(problem, report);
    const Eigen::MatrixXd q = sqrt_mass.asDiagonal() * problem.coordinates;
    report.seconds_factorization += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    Eigen::MatrixXd y;
    if (g.second_order) {
        // Eq. 9 as the paper solves it: one CG on the whole second-order operator.
        const SecondOrderCoefficients& c = *g.second_order;
        const Eigen::MatrixXd rhs = pcg.polynomial({c.b0, c.b1, c.b2}, q);
        y = c(0) * q;  // the low-frequency answer is a good start
        pcg.solve(c.a0, c.a1, c.a2, rhs, y, allowed_error(problem), 0.1);
    } else {
        y = apply_cascade(g, q, allowed_error(problem), spectrum_upper_bound(pcg.kt()), pcg);
    }
    report.seconds_solve += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() -
                            report.seconds_factorization;
    return sqrt_mass.cwiseInverse().asDiagonal() * y;
}

} // namespace geofilter::detail
