#include "exact_pair.h"

#include "cascade.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace geofilter::detail {

namespace {

bool factor_needed_elsewhere(const TransferFunction& g, std::complex<double> r, double shift) {
    const auto same = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(a, b); };
    for (const std::complex<double>& p : g.poles)
        if (p.imag() >= 0 && p != r && same(p.imag() == 0 ? -p.real() : std::abs(p), shift)) return true;
    return false;
}

} // namespace

bool exact_pair_pays(const TransferFunction& g, std::complex<double> r, double shift, bool real_factor_held,
                     const PairSolveCosts& costs) {
    if (factor_needed_elsewhere(g, r, shift)) return false;
    const PreconditionedRange range = pair_preconditioner_range(r, shift);
    const double condition = range.high / range.low;
    const double iterations = costs.last_pair_iterations > 0
                                  ? costs.last_pair_iterations * std::sqrt(condition / costs.last_pair_condition)
                                  : 6.5 * std::sqrt(condition);
    const double cg = (real_factor_held ? 0.0 : costs.real_factorization) + iterations * costs.pair_iteration;
    return cg > costs.complex_factorization;
}

ExactPairSolution solve_pair_exactly(ComplexShiftedFactor& factor, std::complex<double> r, const Eigen::MatrixXd& y,
                                     double allowed_error, const BlockOperator& kt_times, const BlockNorm& norm) {
    const double bound_per_residual = 1 / (std::sqrt(pair_operator_lower_bound(r)) * std::abs(r.imag()));
    const double y_norm = std::max(norm(y), 1e-300);
    Eigen::MatrixXcd z = factor.solve(y.cast<std::complex<double>>());
    Eigen::MatrixXd kt_re, kt_im;
    for (int refinement = 0;; ++refinement) {
        const Eigen::MatrixXd z_re = z.real(), z_im = z.imag();
        kt_times(z_re, kt_re);
        kt_times(z_im, kt_im);
        Eigen::MatrixXcd rho(y.rows(), y.cols());
        rho.real() = y - kt_re + r.real() * z_re - r.imag() * z_im;
        rho.imag() = r.real() * z_im + r.imag() * z_re - kt_im;
        Eigen::MatrixXd parts(y.rows(), 2 * y.cols());
        parts << rho.real(), rho.imag();
        const double residual = norm(parts);
        if (residual * bound_per_residual <= allowed_error) return {Eigen::MatrixXd(z.imag() / r.imag()), residual / y_norm};
        if (refinement == 3)
            throw Error("its error bound stayed " + format_number(residual * bound_per_residual / allowed_error, 3) +
                        " times what the tolerance allows");
        z += factor.solve(rho);
    }
}

std::optional<Eigen::MatrixXd> solve_pair_exactly_or_explain(ExactPairState& state, const ExactPairSteps& steps,
                                                             std::complex<double> r, const Eigen::MatrixXd& y,
                                                             double allowed_error, FilterReport& report) {
    using clock = std::chrono::steady_clock;
    const auto seconds_since = [](clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); };
    const auto give_up = [&](const std::string& why) -> std::optional<Eigen::MatrixXd> {
        state.factor.reset();
        state.note = "complex pole pairs by CG: the exact solve was not used (" + why + ")";
        report.exact_pair_note = state.note;
        return std::nullopt;
    };
    try {
        if (!state.factor) {
            if (steps.progress) steps.progress("analysing for the exact pole-pair solve");
            const auto t = clock::now();
            state.factor = steps.make_factor();
            report.seconds_factorization += seconds_since(t);
        }
        if (!state.factor->holds(r)) {
            if (const std::string shortfall = steps.memory_shortfall(state.factor->estimated_factorization_bytes());
                !shortfall.empty())
                return give_up(shortfall);
            if (steps.progress) steps.progress("factorising Kt - r I");
            const auto t = clock::now();
            state.factor->factorize(r);
            state.seconds_per_factorization = seconds_since(t);
            report.seconds_factorization += state.seconds_per_factorization;
        }
        const auto t = clock::now();
        const ExactPairSolution solved = solve_pair_exactly(*state.factor, r, y, allowed_error, steps.kt_times, steps.norm);
        report.relative_residual = std::max(report.relative_residual, solved.relative_residual);
        report.seconds_solve += seconds_since(t);
        ++report.exact_pairs;
        report.exact_pair_method = state.factor->name();
        return solved.x;
    } catch (const std::exception& e) {
        return give_up(e.what());
    }
}

} // namespace geofilter::detail
