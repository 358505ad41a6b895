#include "core/filter/filter.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <random>

using namespace geofilter;
using namespace geofilter::reference;

namespace {

double direct_eq16(const PoleZeroSpec& p, double s) {
    double g = p.G0;
    for (double z : p.zeros) g *= (s + z) / z;
    for (double q : p.poles) g *= q / (s + q);
    return g;
}

} // namespace

TEST(PoleZero, TransferFunctionMatchesDirectEvaluationForRandomSets) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> log_corner(0, 4), gain(0.1, 3);
    std::uniform_int_distribution<int> count(0, 4);
    for (int trial = 0; trial < 200; ++trial) {
        PoleZeroSpec p;
        p.G0 = gain(rng);
        for (int i = count(rng); i > 0; --i) p.zeros.push_back(std::pow(10.0, log_corner(rng)));
        for (int i = count(rng); i > 0; --i) p.poles.push_back(std::pow(10.0, log_corner(rng)));
        const TransferFunction g = design_pole_zero(p);
        EXPECT_NEAR(g(0), p.G0, 1e-12 * p.G0);
        for (double s : {0.5, 10.0, 333.0, 1e5}) EXPECT_NEAR(g(s), direct_eq16(p, s), 1e-10 * std::abs(direct_eq16(p, s)));
        if (p.zeros.size() == p.poles.size()) {
            double lim = p.G0;
            for (double z : p.zeros) lim /= z;
            for (double q : p.poles) lim *= q;
            EXPECT_NEAR(g.at_infinity(), lim, 1e-12 * lim);
        }
    }
}

TEST(PoleZero, RefusesNonPositiveOrNonFiniteCornersAndWarnsOnMoreZerosThanPoles) {
    EXPECT_THROW(design_pole_zero({1, {0}, {}}), Error);
    EXPECT_THROW(design_pole_zero({1, {}, {-5}}), Error);
    EXPECT_THROW(design_pole_zero({1, {NAN}, {}}), Error);
    EXPECT_THROW(design_pole_zero({INFINITY, {}, {3}}), Error);
    std::vector<std::string> warnings;
    const TransferFunction g = design_pole_zero({1, {10, 20}, {5}}, &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("grows without bound"), std::string::npos);
    EXPECT_TRUE(std::isinf(g.at_infinity()));
}

TEST(PoleZero, CascadeEqualsExactSpectralFilter) {
    Mesh m = torus(40, 25, 1.0, 0.35);
    perturb_radially(m, 0.02, 11);
    const Spectrum spectrum = spectrum_of(m);
    const double diag = bbox_diagonal(m.points);
    const PoleZeroSpec cases[] = {
        {1, {}, {40}},                 // lowpass: one pole
        {1, {100, 400}, {30, 2000}},   // band-stop (Fig. 8): two zeros between two poles
        {1, {60}, {600}},              // high-frequency boost by 10
    };
    for (Solver solver : {Solver::Factored, Solver::JacobiPcg})
        for (const auto& c : cases) {
            const TransferFunction g = design_pole_zero(c);
            FilterOptions options;
            options.solver = solver;
            const Points out = apply_filter(m.points, m.triangles, g, options);
            EXPECT_LT((out - spectral_filter(spectrum, m.points, g)).rowwise().norm().maxCoeff(), 1e-6 * diag)
                << solver_name(solver) << " poles " << c.poles.size() << " zeros " << c.zeros.size();
        }
}

TEST(PoleZero, SphereScalesByGAtTwoOverRSquared) {
    const TransferFunction g = design_pole_zero({1, {100, 400}, {30, 2000}});
    for (double r : {0.1, 0.3, 1.0}) {
        const Mesh s = icosphere(4, r);
        const double ratio = mean_radius(apply_filter(s.points, s.triangles, g)) / r;
        EXPECT_NEAR(ratio, g(2 / (r * r)), 0.02 * g(2 / (r * r))) << "r = " << r;
    }
}
