// The paper's solver (section 2.4): Jacobi-preconditioned CG on eq. 9, matrix-free.
// It runs in the frame q = M^1/2 p, where eq. 9 becomes D(Kt) q' = N(Kt) q with
// Kt = M^-1/2 K M^-1/2. Jacobi preconditioning is invariant under that diagonal
// similarity, so the iterates are the paper's. Its cost grows as s1 falls (the condition
// number is ~ a2 lambda_max^2 / a0): kept as the reference the fast solver is checked against.
#include "pcg.h"
#include "solvers.h"

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

// Solves (c0 + c1 Kt + c2 Kt^2) x = b, starting from x.
PcgOutcome solve_quadratic(const SparseMatrix& kt, const Eigen::VectorXd& kt_diagonal, const Eigen::VectorXd& kt2_diagonal,
                           double c0, double c1, double c2, const Eigen::MatrixXd& b, Eigen::MatrixXd& x,
                           const FilterOptions& options, double progress_base) {
    const BlockOperator matrix = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
        const Eigen::MatrixXd k_in = kt * in;
        out = c0 * in + c1 * k_in;
        if (c2 != 0) out += c2 * (kt * k_in);
    };
    const Eigen::VectorXd inverse_diagonal =
        (Eigen::VectorXd::Constant(kt.rows(), c0) + c1 * kt_diagonal + c2 * kt2_diagonal).cwiseInverse();
    const BlockOperator jacobi = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
        out = inverse_diagonal.asDiagonal() * in;
    };
    const double log_tol = std::log(options.tolerance);
    return block_pcg(matrix, jacobi, b, x, options.tolerance, options.max_iterations, [&](int, double residual) {
        const double fraction = std::clamp(std::log(std::max(residual, 1e-300)) / log_tol, 0.0, 1.0);
        return !options.progress || options.progress(progress_base + 0.4 * fraction, "solving (Jacobi-PCG)");
    });
}

} // namespace

Eigen::MatrixXd solve_jacobi_pcg(const FilterProblem& problem, FilterReport& report) {
    const auto t0 = std::chrono::steady_clock::now();
    const TransferFunction& g = problem.g;
    const Eigen::VectorXd sqrt_mass = problem.laplacian.mass.cwiseSqrt();
    const SparseMatrix kt = mass_normalized_stiffness(problem.laplacian);
    const Eigen::VectorXd kt_diagonal = kt.diagonal();
    const Eigen::VectorXd kt2_diagonal = diagonal_of_square(kt);
    const Eigen::MatrixXd q = sqrt_mass.asDiagonal() * problem.coordinates;
    report.seconds_factorization += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    auto check = [&](const PcgOutcome& outcome) {
        report.iterations += outcome.iterations;
        report.relative_residual = std::max(report.relative_residual, outcome.relative_residual);
        if (outcome.cancelled) throw Error("cancelled by the user");
        if (!outcome.converged)
            throw Error("the Jacobi-PCG solver did not converge in " + std::to_string(outcome.iterations) +
                        " iterations (relative residual " + std::to_string(outcome.relative_residual) +
                        "); raise the iteration cap or use the factored solver");
    };

    Eigen::MatrixXd y;
    if (g.second_order) {
        // Eq. 9 as the paper solves it: one CG on the whole second-order operator.
        const SecondOrderCoefficients& c = *g.second_order;
        Eigen::MatrixXd rhs = c.b0 * q;
        const Eigen::MatrixXd kq = kt * q;
        rhs += c.b1 * kq;
        if (c.b2 != 0) rhs += c.b2 * (kt * kq);
        y = c(0) * q;  // the low-frequency answer is a good start
        check(solve_quadratic(kt, kt_diagonal, kt2_diagonal, c.a0, c.a1, c.a2, rhs, y, problem.options, 0.1));
    } else {
        // A cascade: numerator factor k, then pole k, each pole by its own Jacobi-PCG.
        y = q;
        size_t next_pole = 0;
        for (size_t k = 0; k < std::max(g.numerator.size(), g.poles.size()); ++k) {
            if (k < g.numerator.size()) y = apply_polynomial(kt, g.numerator[k], y);
            if (next_pole >= g.poles.size()) continue;
            const std::complex<double> r = g.poles[next_pole];
            Eigen::MatrixXd x = y;
            if (r.imag() == 0) {
                check(solve_quadratic(kt, kt_diagonal, kt2_diagonal, -r.real(), 1, 0, y, x, problem.options, 0.1));
                next_pole += 1;
            } else {
                check(solve_quadratic(kt, kt_diagonal, kt2_diagonal, std::norm(r), -2 * r.real(), 1, y, x, problem.options,
                                      0.1));
                next_pole += 2;
            }
            y.swap(x);
        }
        y *= g.gain;
    }
    report.seconds_solve += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() -
                            report.seconds_factorization;
    return sqrt_mass.cwiseInverse().asDiagonal() * y;
}

} // namespace geofilter::detail
