// The pair solve from one real Krylov space (shifted_pair_cg.h) against the dense spectral
// solve: at the ideal shift and with a factor held far from it (a Preview's gain change), its
// result within the tolerance and its error bound above the true error.
#include "core/design/butterworth.h"
#include "core/design/transfer_function.h"
#include "core/filter/filter.h"
#include "core/operators/laplace.h"
#include "core/solve/cascade.h"
#include "core/solve/pcg.h"
#include "core/solve/shifted_cholesky.h"
#include "core/solve/shifted_pair_cg.h"
#include "core/solve/solvers.h"
#include "shapes.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <complex>

using namespace geofilter;

namespace {

struct DenseSpectrum {
    SparseMatrix kt;
    Eigen::VectorXd values;
    Eigen::MatrixXd vectors;
};

const DenseSpectrum& torus_spectrum() {
    static const DenseSpectrum spectrum = [] {
        Mesh m = torus(40, 30, 1.0, 0.4);
        perturb_radially(m, 0.01, 7);
        DenseSpectrum s;
        s.kt = mass_normalized_stiffness(cotan_laplacian(m.points, m.triangles));
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig{Eigen::MatrixXd(s.kt)};
        s.values = eig.eigenvalues().cwiseMax(0.0);
        s.vectors = eig.eigenvectors();
        return s;
    }();
    return spectrum;
}

// ((Kt - r)(Kt - conj r))^-1 y from the eigenvectors.
Eigen::MatrixXd dense_pair_solve(const DenseSpectrum& s, std::complex<double> r, const Eigen::MatrixXd& y) {
    Eigen::VectorXd inverse(s.values.size());
    for (Eigen::Index i = 0; i < s.values.size(); ++i) inverse[i] = 1 / std::norm(s.values[i] - r);
    return s.vectors * (inverse.asDiagonal() * (s.vectors.transpose() * y));
}

const std::vector<SecondOrderSpec> specs = {{25, 50, 1, 1.1, 0}, {25, 50, 1, 1.5, 0}, {630, 1260, 1, 0.01, 1.1},
                                            {25, 60, 1, 3, 0.9}, {10, 25, 1, 30, 0}};

} // namespace

TEST(ShiftedPairCg, MatchesTheDenseSpectralSolveAtAnyHeldShift) {
    const DenseSpectrum& s = torus_spectrum();
    detail::ShiftedCholesky cholesky(s.kt);
    const Eigen::MatrixXd y = Eigen::MatrixXd::Random(s.kt.rows(), 3);
    for (const SecondOrderSpec& spec : specs) {
        const std::complex<double> r = design_second_order(spec).poles.at(0);
        ASSERT_NE(r.imag(), 0);
        const Eigen::MatrixXd expected = dense_pair_solve(s, r, y);
        for (double factor : {0.05, 0.3, 1.0, 3.0, 20.0}) {
            SCOPED_TRACE("G1 = " + format_number(spec.G1) + ", shift = " + format_number(factor) + " |r|");
            const double shift = factor * std::abs(r);
            cholesky.factorize(shift);
            const BlockOperator solve = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
                out = cholesky.solve(in);
            };
            const double allowed = 1e-9 * expected.norm();
            Eigen::MatrixXd x = Eigen::MatrixXd::Zero(y.rows(), y.cols());
            const PcgOutcome outcome = detail::sum_shifted_solves(solve, shift, {detail::pair_term(r)}, y, x, allowed, 1000);
            ASSERT_TRUE(outcome.converged);
            const double error = (x - expected).norm();
            EXPECT_LE(error, allowed);
            EXPECT_LE(error, outcome.error_bound * (1 + 1e-6) + 1e-14 * expected.norm());  // a bound
            EXPECT_GT(outcome.iterations, 0);
        }
    }
}

// The rate at shift |r| is, per solve with the factor, what CG on the real pair
// preconditioned by (Kt + |r|)^2 gets: (sqrt(k) - 1) / (sqrt(k) + 1) per iteration of two solves,
// k = 1 / sin^2(arg r / 2).
TEST(ShiftedPairCg, RateAtTheIdealShiftIsTheRealPairCgsPerSolve) {
    for (const SecondOrderSpec& spec : specs) {
        const std::complex<double> r = design_second_order(spec).poles.at(0);
        const double k = 1 / std::pow(std::sin(std::arg(r) / 2), 2);
        const double rate = detail::shifted_pair_rate(r, std::abs(r));
        EXPECT_NEAR(rate * rate, (std::sqrt(k) - 1) / (std::sqrt(k) + 1), 1e-12) << format_number(spec.G1);
    }
}

// A Preview's gain change (G1 1.1 -> 1.5) solved with the factor held at the old pole's shift:
// fewer solves with the factor than CG on the real pair preconditioned by its square.
TEST(ShiftedPairCg, AHeldFactorAtAnotherShiftNeedsFewerSolvesThanCgOnTheRealPair) {
    const DenseSpectrum& s = torus_spectrum();
    const std::complex<double> held = design_second_order({25, 50, 1, 1.1, 0}).poles.at(0);
    const std::complex<double> r = design_second_order({25, 50, 1, 1.5, 0}).poles.at(0);
    const double shift = std::abs(held);
    detail::ShiftedCholesky cholesky(s.kt);
    cholesky.factorize(shift);
    const Eigen::MatrixXd y = Eigen::MatrixXd::Random(s.kt.rows(), 3);
    const Eigen::MatrixXd expected = dense_pair_solve(s, r, y);
    const double allowed = 1e-9 * expected.norm();

    Eigen::MatrixXd shifted = Eigen::MatrixXd::Zero(y.rows(), 3);
    const PcgOutcome by_shift = detail::sum_shifted_solves(
        [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) { out = cholesky.solve(in); }, shift, {detail::pair_term(r)},
        y, shifted, allowed, 1000);
    ASSERT_TRUE(by_shift.converged);
    EXPECT_LE((shifted - expected).norm(), allowed);

    // The tightest bound CG on the pair can stop on for this mesh: the preconditioned operator's
    // smallest eigenvalue, from the spectrum itself, times A's.
    double low = 1e300;
    for (Eigen::Index i = 0; i < s.values.size(); ++i) low = std::min(low, std::norm(s.values[i] - r) / std::pow(s.values[i] + shift, 2));
    const double lower = low * s.values.unaryExpr([&](double v) { return std::norm(v - r); }).minCoeff();
    Eigen::MatrixXd real = Eigen::MatrixXd::Zero(y.rows(), 3);
    const PcgOutcome by_pair = block_pcg(
        [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
            const Eigen::MatrixXd k_in = s.kt * in;
            out = s.kt * k_in - 2 * r.real() * k_in + std::norm(r) * in;
        },
        [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) { out = cholesky.solve(cholesky.solve(in)); }, y, real,
        [&](const Eigen::MatrixXd&, const Eigen::ArrayXd& rz) { return std::sqrt(std::max(rz.sum(), 0.0) / lower); },
        allowed, 1000);
    ASSERT_TRUE(by_pair.converged);
    EXPECT_LE((real - expected).norm(), allowed);
    const int solves_by_shift = by_shift.iterations + 1, solves_by_pair = 2 * (by_pair.iterations + 1);
    EXPECT_LT(solves_by_shift, solves_by_pair);
    RecordProperty("solves", std::to_string(solves_by_shift) + " against " + std::to_string(solves_by_pair));
}

// A Butterworth's poles all call for the factor at |r| = sc: in partial fractions they are
// solved together from one Krylov space, and the result is the dense spectral filter's within
// the tolerance (area-weighted RMS, as FilterOptions::tolerance promises), at every order.
TEST(ShiftedPairCg, AButterworthsPolesSolvedTogetherMeetTheTolerance) {
    Mesh m = torus(40, 25, 1.0, 0.35);
    perturb_radially(m, 0.02, 11);
    const reference::Spectrum spectrum = reference::spectrum_of(m);
    const double diag = reference::bbox_diagonal(m.points);
    for (double sc : {60.0, 400.0})
        for (int n = 3; n <= butterworth_max_order; ++n) {
            SCOPED_TRACE("n = " + std::to_string(n) + ", sc = " + format_number(sc));
            const TransferFunction g = design_butterworth_lowpass(sc, n);
            FilterReport report;
            const Points out = apply_filter(m.points, m.triangles, g, {}, &report);
            EXPECT_EQ(report.poles_at_one_shift, n);
            EXPECT_LE(reference::area_weighted_rms(out - reference::spectral_filter(spectrum, m.points, g), spectrum.mass),
                      1e-7 * diag);
        }
}
