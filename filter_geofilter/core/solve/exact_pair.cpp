#include "core/solve/exact_pair.h"

#include "core/solve/cascade.h"
#include "core/solve/shifted_pair_cg.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace geofilter::detail {

namespace {

bool factor_needed_elsewhere(const TransferFunction& g, std::complex<double> r, double shift) {
    const auto same = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(a, b); };
    for (const std::complex<double>& p : g.poles)
        if (p.imag() >= 0 && p != r && same(factor_shift_for(p), shift)) return true;
    return false;
}

} // namespace

bool exact_pair_pays(const TransferFunction& g, std::complex<double> r, double shift, bool real_factor_held,
                     const PairSolveCosts& costs) {
    if (factor_needed_elsewhere(g, r, shift)) return false;
    const double iterations = shifted_pair_iterations(r, shift, costs.last_pair_iterations, costs.last_pair_rate);
    const double cg = (real_factor_held || costs.session ? 0.0 : costs.real_factorization) + iterations * costs.pair_iteration;
    return cg > (costs.session ? 2 : 1) * costs.complex_factorization;
}

ExactPairSolution solve_pair_exactly(ComplexShiftedFactor& factor, std::complex<double> r, const Eigen::MatrixXd& y,
                                     double allowed_error, const BlockOperator& kt_times, const BlockNorm& norm) {
    // A refinement that does not divide the residual by this much is limited by the factor's
    // precision: a double-precision factor then costs less than the refinements still needed.
    constexpr double least_gain = 10;
    constexpr int most_refinements = 6;
    const double bound_per_residual = 1 / (std::sqrt(pair_operator_lower_bound(r)) * std::abs(r.imag()));
    const double y_norm = std::max(norm(y), 1e-300);
    // Real and imaginary parts one at a time: these vectors add to the factor's memory.
    Eigen::MatrixXcd z = factor.solve(y.cast<std::complex<double>>());
    Eigen::MatrixXd part, kt_part;
    Eigen::MatrixXcd rho(y.rows(), y.cols());
    double previous = std::numeric_limits<double>::infinity();
    int solves = 1;
    for (int refinement = 0;; ++refinement) {
        part = z.real();
        kt_times(part, kt_part);
        rho.real() = y - kt_part + r.real() * part - r.imag() * z.imag();
        part = z.imag();
        kt_times(part, kt_part);
        rho.imag() = r.real() * part + r.imag() * z.real() - kt_part;
        part = rho.real();
        const double real_norm = norm(part);
        part = rho.imag();
        const double residual = std::hypot(real_norm, norm(part));
        if (residual * bound_per_residual <= allowed_error)
            return {Eigen::MatrixXd(z.imag() / r.imag()), residual / y_norm, solves - 1};
        if (refinement == most_refinements || residual * least_gain > previous) {
            if (!factor.raise_precision())
                throw Error("its error bound stayed " + format_number(residual * bound_per_residual / allowed_error, 3) +
                            " times what the tolerance allows");
            z = factor.solve(y.cast<std::complex<double>>());
            ++solves;
            previous = std::numeric_limits<double>::infinity();
            refinement = -1;
            continue;
        }
        previous = residual;
        z += factor.solve(rho);
        ++solves;
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
        report.exact_pair_refinements += solved.refinements;
        report.exact_pair_method = state.factor->name();
        return solved.x;
    } catch (const std::exception& e) {
        return give_up(e.what());
    }
}

} // namespace geofilter::detail
