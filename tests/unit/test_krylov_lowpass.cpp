// The Krylov lowpass against the dense spectral filter.
#include "core/design/butterworth.h"
#include "core/filter/filter.h"
#include "core/operators/operators.h"
#include "core/solve/krylov_lowpass.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <random>

using namespace geofilter;
using namespace geofilter::reference;

namespace {

Mesh noisy_sheet(int n, double sigma, unsigned seed) {
    Mesh m = wavy_sheet(n);
    std::mt19937 random(seed);
    std::normal_distribution<double> gauss(0.0, sigma);
    for (Eigen::Index i = 0; i < m.points.rows(); ++i)
        for (int k = 0; k < 3; ++k) m.points(i, k) += gauss(random);
    return m;
}

double mass_norm(const Eigen::MatrixXd& x, const Eigen::VectorXd& mass) {
    return std::sqrt((mass.array() * x.rowwise().squaredNorm().array()).sum());
}

} // namespace

// On a noisy open sheet, for the umbrella and the cotangent operator, Butterworth lowpasses of
// orders 1-5 (a real pole, complex pairs, both) cut from the lowest frequencies to near the top
// of the spectrum, and the second-order lowpass preset: the Krylov lowpass is within its own
// error bound of the exact one (eigen-decomposition), that bound within what was allowed, in
// fewer steps than there are vertices.
TEST(KrylovLowpass, MatchesTheSpectralLowpassWithinItsBound) {
    const Mesh m = noisy_sheet(16, 0.004, 5);
    for (Operator op : {Operator::Umbrella, Operator::Cotangent}) {
        const Laplacian l = build_laplacian(op, m.points, m.triangles);
        const Spectrum s = dense_spectrum(Eigen::MatrixXd(l.stiffness), l.mass);
        const double top = s.eigenvalues.maxCoeff();
        std::vector<std::pair<std::string, TransferFunction>> filters;
        for (int order : {1, 2, 4, 5})
            for (double fraction : {0.01, 0.05, 0.2, 0.6})
                filters.emplace_back("Butterworth order " + std::to_string(order) + " at " + std::to_string(fraction) + " of the top",
                                     design_butterworth_lowpass(fraction * top, order));
        filters.emplace_back("second-order lowpass", design_second_order({0.02 * top, 0.04 * top, 1.0, 1.1, 0.0}));
        for (const auto& [name, g] : filters) {
            const Points exact = spectral_filter(s, m.points, g);
            const double removed = mass_norm(m.points - exact, l.mass);
            for (double allowed : {1e-3 * removed, 1e-8 * removed}) {
                KrylovReport report;
                const Points approx = krylov_lowpass(l, m.points, g, allowed, 2000, &report);
                const double error = mass_norm(approx - exact, l.mass);
                SCOPED_TRACE(std::string(operator_name(op)) + ", " + name + ", " + std::to_string(report.iterations) + " steps");
                EXPECT_TRUE(report.converged);
                EXPECT_GT(removed, 0);
                EXPECT_LE(report.error_bound, allowed);
                EXPECT_LE(error, report.error_bound + 1e-12 * removed);
                EXPECT_LT(report.iterations, m.points.rows() / 2);
            }
        }
    }
}

// A tighter allowance takes more steps; a step limit too low says so and returns the values as
// given; a transfer function that is not a lowpass with simple poles off the positive
// frequencies is refused.
TEST(KrylovLowpass, StepsFollowTheAllowanceAndLimitsAreReported) {
    const Mesh m = noisy_sheet(16, 0.004, 9);
    const Laplacian l = build_laplacian(Operator::Cotangent, m.points, m.triangles);
    const Spectrum s = dense_spectrum(Eigen::MatrixXd(l.stiffness), l.mass);
    const TransferFunction g = design_butterworth_lowpass(0.02 * s.eigenvalues.maxCoeff(), 4);
    const double removed = mass_norm(m.points - spectral_filter(s, m.points, g), l.mass);
    KrylovReport loose, tight;
    krylov_lowpass(l, m.points, g, 1e-3 * removed, 2000, &loose);
    krylov_lowpass(l, m.points, g, 1e-9 * removed, 2000, &tight);
    EXPECT_LT(loose.iterations, tight.iterations);

    KrylovReport cut;
    const Points c = krylov_lowpass(l, m.points, g, 1e-12 * removed, 4, &cut);
    EXPECT_FALSE(cut.converged);
    EXPECT_GT(cut.error_bound, 1e-12 * removed);
    EXPECT_TRUE(c == m.points);

    SecondOrderSpec not_lowpass;
    not_lowpass.G0 = 0.5;
    EXPECT_THROW(krylov_lowpass(l, m.points, design_second_order(not_lowpass), 1e-6), Error);
    EXPECT_THROW(krylov_lowpass(l, m.points, TransferFunction{}, 1e-6), Error);  // G = 1: no pole
    EXPECT_THROW(krylov_lowpass(l, m.points, g, 0), Error);
}

// apply_filter takes the Lanczos process for a lowpass on the umbrella operator, free or with
// the boundary fixed, and meets the tolerance against the dense spectral filter (the fixed
// boundary's reference: G of the interior operator on the part above the harmonic extension);
// on the cotangent operator, or with G(0) != 1, it factorises as before.
TEST(KrylovLowpass, ApplyFilterTakesItForUmbrellaLowpassesWithinTheTolerance) {
    const Mesh m = noisy_sheet(20, 0.004, 3);
    const double diag = bbox_diagonal(m.points);
    const TransferFunction g = design_butterworth_lowpass(0.3, 4);
    FilterOptions o;
    o.op = Operator::Umbrella;
    o.tolerance = 1e-9;
    FilterReport report;
    const Points out = apply_filter(m.points, m.triangles, g, o, &report);
    EXPECT_GT(report.krylov_steps, 0);
    EXPECT_EQ(report.seconds_factorization, 0.0);
    const Laplacian l = build_laplacian(Operator::Umbrella, m.points, m.triangles);
    const Spectrum s = dense_spectrum(Eigen::MatrixXd(l.stiffness), l.mass);
    const Points exact = spectral_filter(s, m.points, g);
    EXPECT_LE(area_weighted_rms(out - exact, l.mass), 1e-9 * diag);
    EXPECT_GT(area_weighted_rms(m.points - exact, l.mass), 1e-4 * diag);  // the filter acts

    // Fixed boundary: the same result as the factored solver's (both within the tolerance).
    o.fix_boundary = true;
    FilterReport fixed_report, factored_report;
    const Points fixed = apply_filter(m.points, m.triangles, g, o, &fixed_report);
    EXPECT_GT(fixed_report.krylov_steps, 0);
    TransferFunction scaled = g;  // G(0) != 1: factorised
    scaled.gain *= 1 - 1e-9;  // moves each vertex by 1e-9 of its distance to the centroid
    const Points factored = apply_filter(m.points, m.triangles, scaled, o, &factored_report);
    EXPECT_EQ(factored_report.krylov_steps, 0);
    EXPECT_LE((fixed - factored).rowwise().norm().maxCoeff(), 1e-7 * diag);

    FilterReport cotangent;
    apply_filter(m.points, m.triangles, design_butterworth_lowpass(200, 4), {}, &cotangent);
    EXPECT_EQ(cotangent.krylov_steps, 0);
}
