// The Butterworth design against its closed form 1 / (1 + (s/sc)^n), and its application to
// meshes against the dense spectral filter.
#include "core/design/butterworth.h"
#include "core/filter/filter.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <chrono>

using namespace geofilter;
using namespace geofilter::reference;

namespace {

double closed_form(double s, double sc, int n) { return 1.0 / (1.0 + std::pow(s / sc, n)); }

// Ascending coefficients of prod_k (s - p_k) / (-p_k): the denominator of G normalised to 1 at 0.
std::vector<std::complex<double>> normalised_denominator(const std::vector<std::complex<double>>& poles) {
    std::vector<std::complex<double>> c{1.0};
    for (const auto& p : poles) {
        std::vector<std::complex<double>> next(c.size() + 1, 0.0);
        for (size_t i = 0; i < c.size(); ++i) {
            next[i + 1] += c[i] / -p;
            next[i] += c[i];
        }
        c = next;
    }
    return c;
}

} // namespace

TEST(Butterworth, MatchesClosedFormAndHalfGainAtCutoff) {
    for (double sc : {0.5, 30.0, 2e4})
        for (int n = 1; n <= butterworth_max_order; ++n) {
            const TransferFunction g = design_butterworth_lowpass(sc, n);
            EXPECT_NEAR(g(0), 1.0, 1e-14);
            EXPECT_NEAR(g(sc), 0.5, 1e-13) << "n = " << n;
            for (double x : {1e-3, 0.1, 0.7, 1.3, 4.0, 50.0, 1e3})
                EXPECT_NEAR(g(x * sc), closed_form(x * sc, sc, n), 1e-12 * closed_form(x * sc, sc, n) + 1e-300)
                    << "n = " << n << " s/sc = " << x;
            EXPECT_EQ(g.at_infinity(), 0.0);
        }
}

TEST(Butterworth, MaximallyFlatFirstNMinusOneDerivativesVanishAtZero) {
    // G = 1/D with D(0) = 1: G's derivatives 1..n-1 at 0 vanish iff D's coefficients of
    // s..s^(n-1) do; the s^n coefficient must be 1/sc^n.
    const double sc = 7.0;
    for (int n = 1; n <= butterworth_max_order; ++n) {
        const TransferFunction g = design_butterworth_lowpass(sc, n);
        ASSERT_EQ(static_cast<int>(g.poles.size()), n);
        const auto d = normalised_denominator(g.poles);
        EXPECT_NEAR(std::abs(d[0] - 1.0), 0, 1e-14);
        for (int k = 1; k < n; ++k) EXPECT_LT(std::abs(d[k]) * std::pow(sc, k), 1e-12) << "n = " << n << " k = " << k;
        EXPECT_NEAR(std::abs(d[n] * std::pow(sc, n) - 1.0), 0, 1e-12) << "n = " << n;
    }
}

TEST(Butterworth, SlopeIsMinusNDecadesPerDecadeAtHighFrequency) {
    const double sc = 3.0;
    for (int n = 1; n <= butterworth_max_order; ++n) {
        const TransferFunction g = design_butterworth_lowpass(sc, n);
        const double s = 1e4 * sc, h = 1e-3;
        const double slope = (std::log(std::abs(g(s * std::exp(h)))) - std::log(std::abs(g(s * std::exp(-h))))) / (2 * h);
        const double x = std::pow(1e4, n);
        EXPECT_NEAR(slope, -n * x / (1 + x), 1e-6) << "n = " << n;  // d log G / d log s of the closed form
        EXPECT_NEAR(slope, -n, 2e-4 * n) << "n = " << n;
    }
}

TEST(Butterworth, PolesAreTheRootsOfMinusOneOnTheCutoffCircleAndOffTheSpectrum) {
    const double sc = 12.5;
    for (int n = 1; n <= butterworth_max_order; ++n) {
        const TransferFunction g = design_butterworth_lowpass(sc, n);
        ASSERT_EQ(static_cast<int>(g.poles.size()), n);
        for (int k = 0; k < n; ++k) {
            const std::complex<double> expected = std::polar(sc, M_PI * (2 * k + 1) / n);
            double nearest = INFINITY;
            for (const auto& p : g.poles) nearest = std::min(nearest, std::abs(p - expected));
            EXPECT_LT(nearest, 1e-12 * sc) << "n = " << n << " k = " << k;
        }
        for (const auto& p : g.poles) EXPECT_FALSE(p.imag() == 0 && p.real() >= 0);
        // Conjugate pairs are stored next to each other, as the solvers expect.
        for (size_t i = 0; i < g.poles.size(); ++i)
            if (g.poles[i].imag() > 0) EXPECT_EQ(g.poles[i + 1], std::conj(g.poles[i]));
        const ResponseReport r = analyse_response(g, 0, sc * 1e-4, sc * 1e4);
        EXPECT_NEAR(r.peak_gain, 1.0, 1e-12);
        EXPECT_FALSE(r.changes_sign);
    }
}

TEST(Butterworth, RefusesBadOrderAndCutoffNamingTheParameter) {
    for (int n : {0, -1, 9, 100}) {
        try {
            design_butterworth_lowpass(10, n);
            ADD_FAILURE() << "order " << n << " accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("order"), std::string::npos);
        }
    }
    for (double sc : {0.0, -3.0, double(NAN), double(INFINITY)}) {
        try {
            design_butterworth_lowpass(sc, 4);
            ADD_FAILURE() << "cutoff " << sc << " accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("cutoff"), std::string::npos);
        }
    }
}

TEST(Butterworth, FactoredCascadeEqualsDenseSpectralFilterForEveryOrder) {
    Mesh m = torus(40, 25, 1.0, 0.35);
    perturb_radially(m, 0.02, 11);
    const Spectrum spectrum = spectrum_of(m);
    const double diag = bbox_diagonal(m.points);
    for (double sc : {60.0, 400.0})
        for (int n = 1; n <= butterworth_max_order; ++n) {
            const TransferFunction g = design_butterworth_lowpass(sc, n);
            const Points out = apply_filter(m.points, m.triangles, g);
            EXPECT_LT((out - spectral_filter(spectrum, m.points, g)).rowwise().norm().maxCoeff(), 1e-6 * diag)
                << "n = " << n << " sc = " << sc;
        }
}

TEST(Butterworth, JacobiPcgCascadeEqualsDenseSpectralFilter) {
    Mesh m = torus(30, 18, 1.0, 0.35);
    perturb_radially(m, 0.02, 3);
    const Spectrum spectrum = spectrum_of(m);
    const double diag = bbox_diagonal(m.points);
    FilterOptions options;
    options.solver = Solver::JacobiPcg;
    for (int n : {1, 2, 4, 8}) {
        const TransferFunction g = design_butterworth_lowpass(200, n);
        const Points out = apply_filter(m.points, m.triangles, g, options);
        EXPECT_LT((out - spectral_filter(spectrum, m.points, g)).rowwise().norm().maxCoeff(), 1e-6 * diag) << "n = " << n;
    }
}

TEST(Butterworth, SphereScalesByGAtTwoOverRSquared) {
    for (double r : {0.2, 1.0})
        for (int n : {1, 4, 8}) {
            const Mesh s = icosphere(4, r);
            const double sc = 1.5 / (r * r);  // 2/r^2 lies above the cutoff: a visible scaling
            const TransferFunction g = design_butterworth_lowpass(sc, n);
            const double ratio = mean_radius(apply_filter(s.points, s.triangles, g)) / r;
            EXPECT_NEAR(ratio, closed_form(2 / (r * r), sc, n), 2e-3) << "r = " << r << " n = " << n;
        }
}

TEST(Butterworth, OtherOperatorsEqualTheirOwnDenseSpectralFilter) {
    // The operator option reaches the solver: the filter on the intrinsic Delaunay and the
    // umbrella operators equals p' = V G(Lambda) V^-1 p for that operator's K and M.
    Mesh m = torus(30, 18, 1.0, 0.35);
    perturb_radially(m, 0.03, 5);
    const double diag = bbox_diagonal(m.points);
    for (Operator op : {Operator::IntrinsicDelaunay, Operator::Umbrella}) {
        const Laplacian l = build_laplacian(op, m.points, m.triangles);
        const Spectrum spectrum = dense_spectrum(Eigen::MatrixXd(l.stiffness), l.mass);
        const TransferFunction g = design_butterworth_lowpass(op == Operator::Umbrella ? 0.3 : 80.0, 4);
        FilterOptions options;
        options.op = op;
        const Points out = apply_filter(m.points, m.triangles, g, options);
        EXPECT_LT((out - spectral_filter(spectrum, m.points, g)).rowwise().norm().maxCoeff(), 1e-6 * diag)
            << operator_name(op);
    }
}
