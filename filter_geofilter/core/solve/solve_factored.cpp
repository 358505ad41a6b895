// The fast solver. In the frame q = M^1/2 p the operator is the symmetric
// Kt = M^-1/2 K M^-1/2 and the filter is the matrix function G(Kt): a polynomial
// numerator times one solve per pole. All factors are polynomials in the same Kt, so
// they commute and can be applied in any order, and every shifted matrix Kt + c I has
// the same sparsity: CHOLMOD's symbolic analysis is done once per mesh.
#include "core/solve/cascade.h"
#include "core/solve/exact_pair.h"
#include "core/solve/pcg.h"
#include "core/solve/shifted_cholesky.h"
#include "core/solve/shifted_pair_cg.h"
#include "core/solve/solvers.h"

#include <chrono>
#include <cmath>
#include <complex>
#include <memory>
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

// The pieces a factored filter is made of, sharing one matrix, one symbolic analysis and
// one timing report.
class FactoredStages : public PoleGroupSolver {
public:
    FactoredStages(const FilterProblem& problem, FilterReport& report)
        : problem_(problem), report_(report), state_(state_for(problem, report, local_state_)) {}

    const SparseMatrix& kt() const { return state_.kt; }
    Eigen::MatrixXd to_scaled(const Eigen::MatrixXd& p) const { return state_.sqrt_mass.asDiagonal() * p; }
    Eigen::MatrixXd from_scaled(const Eigen::MatrixXd& y) const {
        return state_.sqrt_mass.cwiseInverse().asDiagonal() * y;
    }

    Eigen::MatrixXd polynomial(const std::vector<double>& c, const Eigen::MatrixXd& y) override {
        const auto t = std::chrono::steady_clock::now();
        Eigen::MatrixXd out = apply_polynomial(state_.kt, c, y);
        report_.seconds_solve += seconds_since(t);
        return out;
    }

    // (Kt - r)^-1 y for a real pole r < 0: one factorisation, one exact solve.
    Eigen::MatrixXd real_pole(double r, const Eigen::MatrixXd& y, double, double progress) override {
        if (r >= 0) throw Error("unstable filter: a pole lies at s = " + format_number(r) + " >= 0");
        factorize(-r, progress);
        const auto t = std::chrono::steady_clock::now();
        Eigen::MatrixXd solved = state_.cholesky.solve(y);
        const Eigen::MatrixXd residual = state_.kt * solved - r * solved - y;
        report_.relative_residual = std::max(report_.relative_residual, residual.norm() / std::max(y.norm(), 1e-300));
        report_.seconds_solve += seconds_since(t);
        return solved;
    }

    // ((Kt - r)(Kt - conj r))^-1 y from the Krylov space of (Kt + c)^-1 (shifted_pair_cg.h),
    // c = |r| unless a factor at another shift is already held and reusing it is predicted to
    // be cheaper than a new factorisation (a preview run with a changed frequency). The
    // stopping test is a bound, not an estimate, at any c.
    Eigen::MatrixXd conjugate_pair(std::complex<double> r, const Eigen::MatrixXd& y, double allowed_error,
                                   double progress) override {
        const double shift = preconditioner_shift(r);
        if (state_.exact.failed())
            report_.exact_pair_note = state_.exact.note;  // why every pair on this state is on CG
        else if (exact_pair_pays(r, shift))
            if (std::optional<Eigen::MatrixXd> x = exact_pair(r, y, allowed_error, progress)) return *x;
        const double twice_re = 2 * r.real(), modulus2 = std::norm(r);
        const auto t = std::chrono::steady_clock::now();
        const SparseMatrix& kt = state_.kt;
        const BlockOperator quadratic = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
            const Eigen::MatrixXd k_in = kt * in;
            out = kt * k_in;
            out -= twice_re * k_in;
            out += modulus2 * in;
        };
        Eigen::MatrixXd x = starting_guess(quadratic, y);
        Eigen::MatrixXd rest = y;
        if (!x.isZero(0)) {
            Eigen::MatrixXd a_x;
            quadratic(x, a_x);
            rest -= a_x;
        }
        report_.seconds_solve += seconds_since(t);
        solve_by_shifted_cg({pair_term(r)}, shift, rest, x, allowed_error, progress);
        if (problem_.factor_slot) {
            if (state_.pair_solutions.size() <= pairs_solved_) state_.pair_solutions.resize(pairs_solved_ + 1);
            state_.pair_solutions[pairs_solved_] = x;
        }
        ++pairs_solved_;
        return x;
    }

    // Every pole from the one Krylov space of (Kt + c)^-1, c the poles' shift unless a held
    // factor is predicted to finish sooner, as for a pair.
    std::optional<Eigen::MatrixXd> poles_at_one_shift(const PartialFractions& g, double ideal,
                                                      const Eigen::MatrixXd& y, double allowed_error) override {
        const std::vector<ShiftedTerm> terms = shifted_terms(g);
        Eigen::MatrixXd x = Eigen::MatrixXd::Zero(y.rows(), y.cols());
        solve_by_shifted_cg(terms, shift_for(terms, ideal), y, x, allowed_error, 0.1);
        report_.poles_at_one_shift += static_cast<int>(g.poles.size());
        return x;
    }

private:
    // sum_shifted_solves with the factor at `shift` (made here if it is not held), added to x;
    // its time per iteration and count are kept for the next choice of shift.
    void solve_by_shifted_cg(const std::vector<ShiftedTerm>& terms, double shift, const Eigen::MatrixXd& y,
                             Eigen::MatrixXd& x, double allowed_error, double progress) {
        factorize(shift, progress);
        const auto t = std::chrono::steady_clock::now();
        const BlockOperator solve_shifted = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
            out = state_.cholesky.solve(in);
        };
        const FilterOptions& options = problem_.options;
        const PcgOutcome outcome =
            sum_shifted_solves(solve_shifted, shift, terms, y, x, allowed_error, options.max_iterations,
                               [&](int, double) { return !options.progress || options.progress(progress, "solving"); });
        record_pcg_outcome(outcome, allowed_error, "raise maxIterations or the tolerance", report_);
        const double seconds = seconds_since(t);
        report_.seconds_solve += seconds;
        if (outcome.iterations > 0) {
            state_.seconds_per_pair_iteration = seconds / outcome.iterations;
            state_.last_pair_iterations = outcome.iterations;
            state_.last_pair_rate = slowest_rate(terms, shift);
        }
    }

    static double slowest_rate(const std::vector<ShiftedTerm>& terms, double shift) {
        double rate = 0;
        for (const ShiftedTerm& term : terms)
            if (term.pole.imag() != 0) rate = std::max(rate, shifted_pair_rate(term.pole, shift));
        return rate;
    }

    // Where CG on A x = y starts: zero, or, when an earlier run on this state solved a pair in
    // the same place of its cascade, that solution x_prev scaled by the Galerkin step
    // alpha = <x_prev, y> / <x_prev, A x_prev>, which minimises the A-norm error along x_prev:
    // never further from the answer than zero, for two products with Kt. A preview's
    // parameter change mostly rescales the pair's solution; what CG then has to fix is the
    // change of shape.
    Eigen::MatrixXd starting_guess(const BlockOperator& a, const Eigen::MatrixXd& y) const {
        Eigen::MatrixXd x = Eigen::MatrixXd::Zero(y.rows(), y.cols());
        if (pairs_solved_ >= state_.pair_solutions.size()) return x;
        const Eigen::MatrixXd& previous = state_.pair_solutions[pairs_solved_];
        if (previous.rows() != y.rows() || previous.cols() != y.cols()) return x;
        Eigen::MatrixXd a_previous;
        a(previous, a_previous);
        for (Eigen::Index c = 0; c < y.cols(); ++c) {
            const double curvature = previous.col(c).dot(a_previous.col(c));
            if (curvature > 0) x.col(c) = (previous.col(c).dot(y.col(c)) / curvature) * previous.col(c);
        }
        return x;
    }

    // The shared rule (exact_pair.h), with this state's own timings once it has them.
    bool exact_pair_pays(std::complex<double> r, double shift) const {
        if (!problem_.options.complex_factorization) return false;
        if (state_.exact.holds(r)) return true;
        const bool held = state_.cholesky.has_factor() && state_.cholesky.shift() == shift;
        return detail::exact_pair_pays(problem_.g, r, shift, held, measured_costs());
    }

    // The default ratios (exact_pair.h) in seconds, from whichever factorisation this state
    // has timed. A factorisation of a few milliseconds times the clock and the machine's load,
    // not the solver: there the ratios decide as they are. (A 961-vertex sheet under the
    // sanitizers, the same run three times: the exact pair's measured threshold came out 9.3,
    // 11.2 and 19.1 ms against CG's 12.0, and the choice flipped from run to run.)
    PairSolveCosts measured_costs() const {
        PairSolveCosts costs;
        costs.last_pair_iterations = state_.last_pair_iterations;
        costs.last_pair_rate = state_.last_pair_rate;
        costs.session = problem_.factor_slot != nullptr;
        const double ratio = costs.complex_factorization;
        const double timed = state_.seconds_per_factorization > 0 ? state_.seconds_per_factorization
                                                                  : state_.exact.seconds_per_factorization / ratio;
        if (timed < least_timed_factorization_seconds) return costs;
        costs.real_factorization = timed;
        costs.complex_factorization = state_.exact.seconds_per_factorization > 0
                                          ? state_.exact.seconds_per_factorization
                                          : ratio * costs.real_factorization;
        costs.pair_iteration = state_.seconds_per_factorization > 0 && state_.seconds_per_pair_iteration > 0
                                   ? state_.seconds_per_pair_iteration
                                   : costs.pair_iteration * costs.real_factorization;
        return costs;
    }

    // The pair by a factorisation of Kt - r I (exact_pair.h); empty when that fails or does
    // not fit: CG then solves it.
    std::optional<Eigen::MatrixXd> exact_pair(std::complex<double> r, const Eigen::MatrixXd& y, double allowed_error,
                                              double progress) {
        const FilterOptions& options = problem_.options;
        const SparseMatrix& kt = state_.kt;
        const ExactPairSteps steps{
            [&] { return options.complex_factorization(kt); },
            [](double needed) {
                const double available = available_memory_bytes();
                return available > 0 && needed > available
                           ? "it would need " + format_number(needed / (1 << 20), 3) + " MiB, " +
                                 format_number(available / (1 << 20), 3) + " MiB are available"
                           : std::string();
            },
            [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) { out = kt * in; },
            [](const Eigen::MatrixXd& m) { return m.norm(); },
            [&](const char* stage) { report_progress(options, progress, stage); }};
        return solve_pair_exactly_or_explain(state_.exact, steps, r, y, allowed_error, report_);
    }

    // The cache's state when the problem brings a slot for one, else a state of this run's
    // own; built (the symbolic analysis) when the slot is empty.
    static FactorState& state_for(const FilterProblem& problem, FilterReport& report,
                                  std::unique_ptr<FactorState>& local) {
        std::unique_ptr<FactorState>& slot = problem.factor_slot ? *problem.factor_slot : local;
        if (!slot) {
            report_progress(problem.options, 0.05, "building Kt");
            const auto t = std::chrono::steady_clock::now();
            slot = std::make_unique<FactorState>(problem.laplacian);
            report.seconds_assembly += seconds_since(t);
        }
        return *slot;
    }

    // |r| (the fewest iterations) unless the held factor is predicted to finish sooner.
    double preconditioner_shift(std::complex<double> r) const { return shift_for({pair_term(r)}, std::abs(r)); }

    // The shift to solve `terms` at: `ideal` unless a factor is held at another one and is
    // predicted to finish sooner than a new factorisation and the iterations at `ideal`
    // (shifted_pair_iterations for the slowest pair, calibrated by the last solve on this state).
    double shift_for(const std::vector<ShiftedTerm>& terms, double ideal) const {
        const ShiftedCholesky& cholesky = state_.cholesky;
        if (!cholesky.has_factor() || cholesky.shift() == ideal || state_.seconds_per_pair_iteration <= 0 ||
            state_.seconds_per_factorization <= 0 || state_.last_pair_iterations <= 0)
            return ideal;
        auto predicted_seconds = [&](double shift) {
            double iterations = 0;
            for (const ShiftedTerm& term : terms)
                if (term.pole.imag() != 0)
                    iterations = std::max(iterations, shifted_pair_iterations(term.pole, shift, state_.last_pair_iterations,
                                                                              state_.last_pair_rate));
            return iterations * state_.seconds_per_pair_iteration;
        };
        const double held = predicted_seconds(cholesky.shift());
        const double fresh = state_.seconds_per_factorization + predicted_seconds(ideal);
        return held < fresh ? cholesky.shift() : ideal;
    }

    void factorize(double shift, double progress) {
        if (state_.cholesky.has_factor() && state_.cholesky.shift() == shift) return;
        if (!state_.cholesky.analysed()) {
            report_progress(problem_.options, progress, "analysing the sparsity pattern");
            const auto t = std::chrono::steady_clock::now();
            state_.cholesky.analyse();
            report_.seconds_factorization += seconds_since(t);
        }
        report_progress(problem_.options, progress, "factorising");
        const auto t = std::chrono::steady_clock::now();
        state_.cholesky.factorize(shift);
        const double seconds = seconds_since(t);
        state_.seconds_per_factorization = seconds;
        report_.seconds_factorization += seconds;
    }

    const FilterProblem& problem_;
    FilterReport& report_;
    std::unique_ptr<FactorState> local_state_;
    FactorState& state_;
    size_t pairs_solved_ = 0;  // by CG in this run
};

} // namespace

namespace {

// The shift at which every pole of g calls for the factor (factor_shift_for), if they agree.
std::optional<double> one_shift_for_every_pole(const TransferFunction& g) {
    std::optional<double> shift;
    for (const std::complex<double>& p : g.poles) {
        const double own = factor_shift_for(p);
        if (!(own > 0)) return std::nullopt;
        if (!shift) shift = own;
        else if (std::abs(own - *shift) > 1e-9 * *shift) return std::nullopt;
    }
    return shift;
}

} // namespace

Eigen::MatrixXd solve_factored(const FilterProblem& problem, FilterReport& report) {
    const TransferFunction& g = problem.g;
    FactoredStages stages(problem, report);
    const Eigen::MatrixXd q = stages.to_scaled(problem.coordinates);
    const double allowed = allowed_error(problem);
    return stages.from_scaled(apply_factored_transfer(g, q, allowed, spectrum_upper_bound(stages.kt()), stages));
}

Eigen::MatrixXd apply_factored_transfer(const TransferFunction& g, const Eigen::MatrixXd& q, double allowed_error,
                                        double spectrum_max, PoleGroupSolver& solver) {
    if (g.second_order && g.poles.size() == 2 && g.poles[0].imag() != 0) {
        // G = Ginf + R/D with deg R <= 1: the iterative part only carries the band that G
        // changes, not the whole shape, so it needs fewer iterations for the same accuracy
        // (notch and exaggeration filters have Ginf near 1).
        const SecondOrderCoefficients& c = *g.second_order;
        const double g_inf = c.b2 / c.a2;
        const Eigen::MatrixXd rhs = solver.polynomial({c.b0 - g_inf * c.a0, c.b1 - g_inf * c.a1}, q);
        const Eigen::MatrixXd x = solver.conjugate_pair(g.poles[0], rhs, allowed_error * std::abs(c.a2), 0.5);
        return g_inf * q + x / c.a2;
    }
    const bool several_pole_groups = g.poles.size() > 2 || (g.poles.size() == 2 && g.poles[0].imag() == 0);
    if (several_pole_groups)
        if (const std::optional<double> shift = one_shift_for_every_pole(g))
            if (const std::optional<PartialFractions> fractions = partial_fractions(g))
                if (std::optional<Eigen::MatrixXd> x = solver.poles_at_one_shift(*fractions, *shift, q, allowed_error))
                    return fractions->at_infinity * q + *x;
    return apply_cascade(g, q, allowed_error, spectrum_max, solver);
}

} // namespace geofilter::detail
