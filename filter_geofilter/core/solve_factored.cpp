// The fast solver. In the frame q = M^1/2 p the operator is the symmetric
// Kt = M^-1/2 K M^-1/2 and the filter is the matrix function G(Kt): a polynomial
// numerator times one solve per pole. All factors are polynomials in the same Kt, so
// they commute and can be applied in any order, and every shifted matrix Kt + c I has
// the same sparsity: CHOLMOD's symbolic analysis is done once per mesh.
#include "cascade.h"
#include "pcg.h"
#include "solvers.h"

#include <Eigen/CholmodSupport>

#include <chrono>
#include <cmath>
#include <complex>
#include <optional>

namespace geofilter::detail {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

// CHOLMOD's default tries METIS on large meshes: measured here on a 1M-vertex mesh, its
// analysis took 8.9 s for a factor 15% faster than AMD's, whose analysis took 0.5 s. We
// factorise once or twice per analysis, so AMD wins.
void use_amd_ordering(cholmod_common& common) {
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_AMD;
    common.postorder = 1;
}

namespace {

class ShiftedCholesky {
public:
    explicit ShiftedCholesky(const SparseMatrix& kt) : kt_(kt) {
        use_amd_ordering(llt_.cholmod());
        llt_.analyzePattern(kt_);
        if (llt_.cholmod().status == CHOLMOD_OUT_OF_MEMORY) throw std::bad_alloc();
    }

    // Factorises Kt + shift I unless that factor is already held.
    void factorize(double shift) {
        if (shift == shift_) return;
        llt_.setShift(shift);
        llt_.factorize(kt_);
        if (llt_.cholmod().status == CHOLMOD_OUT_OF_MEMORY) throw std::bad_alloc();
        if (llt_.info() != Eigen::Success)
            throw Error("the sparse Cholesky factorisation failed (Kt + " + format_number(shift) +
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

namespace {

// The pieces a factored filter is made of, sharing one matrix, one symbolic analysis and
// one timing report.
class FactoredStages : public PoleGroupSolver {
public:
    FactoredStages(const FilterProblem& problem, FilterReport& report)
        : problem_(problem), report_(report), sqrt_mass_(problem.laplacian.mass.cwiseSqrt()),
          kt_(mass_normalized_stiffness(problem.laplacian)) {
        report_progress(problem.options, 0.05, "analysing the sparsity pattern");
        const auto t = std::chrono::steady_clock::now();
        cholesky_.emplace(kt_);
        report_.seconds_factorization += seconds_since(t);
    }

    const SparseMatrix& kt() const { return kt_; }
    Eigen::MatrixXd to_scaled(const Eigen::MatrixXd& p) const { return sqrt_mass_.asDiagonal() * p; }
    Eigen::MatrixXd from_scaled(const Eigen::MatrixXd& y) const { return sqrt_mass_.cwiseInverse().asDiagonal() * y; }

    Eigen::MatrixXd polynomial(const std::vector<double>& c, const Eigen::MatrixXd& y) override {
        const auto t = std::chrono::steady_clock::now();
        Eigen::MatrixXd out = apply_polynomial(kt_, c, y);
        report_.seconds_solve += seconds_since(t);
        return out;
    }

    // (Kt - r)^-1 y for a real pole r < 0: one factorisation, one exact solve.
    Eigen::MatrixXd real_pole(double r, const Eigen::MatrixXd& y, double, double progress) override {
        if (r >= 0) throw Error("unstable filter: a pole lies at s = " + format_number(r) + " >= 0");
        factorize(-r, progress);
        const auto t = std::chrono::steady_clock::now();
        Eigen::MatrixXd solved = cholesky_->solve(y);
        const Eigen::MatrixXd residual = kt_ * solved - r * solved - y;
        report_.relative_residual = std::max(report_.relative_residual, residual.norm() / std::max(y.norm(), 1e-300));
        report_.seconds_solve += seconds_since(t);
        return solved;
    }

    // ((Kt - r)(Kt - conj r))^-1 y by CG preconditioned with P = (Kt + |r|)^2. Per eigenvalue
    // l >= 0 of Kt the ratio |l - r|^2 / (l + |r|)^2 lies in [c, 1], c = sin^2(arg(r)/2), so
    // the condition number is at most 1/c whatever the mesh. The stopping test is a bound,
    // not an estimate: with A the pair operator, A >= c P and A >= m I
    // (m = pair_operator_lower_bound(r)), so |x - A^-1 y|^2 = r' A^-2 r <= r' P^-1 r / (c m).
    Eigen::MatrixXd conjugate_pair(std::complex<double> r, const Eigen::MatrixXd& y, double allowed_error,
                                   double progress) override {
        const double modulus = std::abs(r), twice_re = 2 * r.real(), modulus2 = std::norm(r);
        factorize(modulus, progress);
        const auto t = std::chrono::steady_clock::now();
        const BlockOperator quadratic = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
            const Eigen::MatrixXd k_in = kt_ * in;
            out = kt_ * k_in;
            out -= twice_re * k_in;
            out += modulus2 * in;
        };
        const BlockOperator preconditioner = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
            out = cholesky_->solve(cholesky_->solve(in));
        };
        const double sin_half = std::sin(0.5 * std::abs(std::arg(r)));
        const double lower = sin_half * sin_half * pair_operator_lower_bound(r);
        const ErrorBound bound = [&](const Eigen::MatrixXd&, const Eigen::ArrayXd& rz) {
            return std::sqrt(std::max(rz.sum(), 0.0) / lower);
        };
        Eigen::MatrixXd x = Eigen::MatrixXd::Zero(y.rows(), y.cols());
        const FilterOptions& options = problem_.options;
        const PcgOutcome outcome =
            block_pcg(quadratic, preconditioner, y, x, bound, allowed_error, options.max_iterations,
                      [&](int, double) { return !options.progress || options.progress(progress, "solving"); });
        record(outcome, allowed_error);
        report_.seconds_solve += seconds_since(t);
        return x;
    }

private:
    void factorize(double shift, double progress) {
        report_progress(problem_.options, progress, "factorising");
        const auto t = std::chrono::steady_clock::now();
        cholesky_->factorize(shift);
        report_.seconds_factorization += seconds_since(t);
    }

    void record(const PcgOutcome& outcome, double allowed_error) {
        report_.iterations += outcome.iterations;
        report_.relative_residual = std::max(report_.relative_residual, outcome.relative_residual);
        if (outcome.cancelled) throw Error("cancelled by the user");
        if (!outcome.converged)
            throw Error("the solver did not converge in " + std::to_string(outcome.iterations) +
                        " iterations (its error bound is " + format_number(outcome.error_bound / allowed_error) +
                        " times what the tolerance allows); raise maxIterations or the tolerance");
    }

    const FilterProblem& problem_;
    FilterReport& report_;
    Eigen::VectorXd sqrt_mass_;
    SparseMatrix kt_;
    std::optional<ShiftedCholesky> cholesky_;
};

} // namespace

Eigen::MatrixXd solve_factored(const FilterProblem& problem, FilterReport& report) {
    const TransferFunction& g = problem.g;
    FactoredStages stages(problem, report);
    const Eigen::MatrixXd q = stages.to_scaled(problem.coordinates);
    const double allowed = allowed_error(problem);

    if (g.second_order && g.poles.size() == 2 && g.poles[0].imag() != 0) {
        // G = Ginf + R/D with deg R <= 1: the iterative part only carries the band that G
        // changes, not the whole shape, so it needs fewer iterations for the same accuracy
        // (notch and exaggeration filters have Ginf near 1).
        const SecondOrderCoefficients& c = *g.second_order;
        const double g_inf = c.b2 / c.a2;
        const Eigen::MatrixXd rhs = stages.polynomial({c.b0 - g_inf * c.a0, c.b1 - g_inf * c.a1}, q);
        const Eigen::MatrixXd x = stages.conjugate_pair(g.poles[0], rhs, allowed * std::abs(c.a2), 0.5);
        return stages.from_scaled(g_inf * q + x / c.a2);
    }
    return stages.from_scaled(apply_cascade(g, q, allowed, spectrum_upper_bound(stages.kt()), stages));
}

} // namespace geofilter::detail
