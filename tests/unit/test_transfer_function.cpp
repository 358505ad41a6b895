#include "core/transfer_function.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace geofilter;

namespace {

// PAPER-NOTES section 9: every parameter set of the paper's figures.
const SecondOrderSpec paper_sets[] = {
    {20, 25, 1, 2, 0},      {20, 25, 1, 2, 0.9},    {10, 25, 1, 30, 0},      {630, 1260, 1, 3, 0.9},
    {630, 1260, 1, 0.01, 1.1}, {25, 60, 1, 3, 0},   {25, 60, 1, 3, 0.9},     {60, 120, 1, 2, 0.9},
    {25, 50, 1, 1.1, 0},    {200, 1000, 0.5, 1.1, 0}, {25, 400, 0.5, 1.1, 0.5},
};

std::string name_of(const SecondOrderSpec& s) {
    return "s1=" + std::to_string(s.s1) + " s2=" + std::to_string(s.s2) + " G0=" + std::to_string(s.G0) +
           " G1=" + std::to_string(s.G1) + " Ginf=" + std::to_string(s.Ginf);
}

} // namespace

// PAPER-NOTES section 2: G(0) = G0, G(s1) = G1, G'(s1) = 0, G(s2) = 1, G(inf) = Ginf.
TEST(TransferFunction, Eq15MeetsItsFiveDesignConditionsForEveryPaperSet) {
    for (const auto& spec : paper_sets) {
        const TransferFunction g = design_second_order(spec);
        const SecondOrderCoefficients& c = *g.second_order;
        SCOPED_TRACE(name_of(spec));
        EXPECT_NEAR(g(0), spec.G0, 1e-12);
        EXPECT_NEAR(g(spec.s1), spec.G1, 1e-9 * std::max(1.0, spec.G1));
        const double h = 1e-5 * spec.s1;
        const double slope = (g(spec.s1 + h) - g(spec.s1 - h)) / (2 * h);
        EXPECT_NEAR(slope * spec.s1, 0, 1e-6 * std::max(1.0, spec.G1));
        EXPECT_NEAR(g(spec.s2), 1.0, 1e-9);
        EXPECT_NEAR(g.at_infinity(), spec.Ginf, 1e-12);
        EXPECT_NEAR(g(1e9 * spec.s1), spec.Ginf, 1e-6);
        // The factored form the solvers use is the same function as the rational one.
        for (double s : {0.0, 0.3 * spec.s1, spec.s1, spec.s2, 7 * spec.s2})
            EXPECT_NEAR(g(s), c(s), 1e-9 * std::max(1.0, std::abs(c(s))));
        EXPECT_DOUBLE_EQ(c.a0, 1);
        EXPECT_DOUBLE_EQ(c.b0, spec.G0);
    }
}

TEST(TransferFunction, RefusesEachInvalidParameterByName) {
    auto message = [](const SecondOrderSpec& s) {
        try {
            design_second_order(s);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(message({0, 50, 1, 1.1, 0}).find("s1 must be > 0"), std::string::npos);
    EXPECT_NE(message({-3, 50, 1, 1.1, 0}).find("s1 must be > 0"), std::string::npos);
    EXPECT_NE(message({25, 0, 1, 1.1, 0}).find("s2 must be > 0"), std::string::npos);
    EXPECT_NE(message({25, -1, 1, 1.1, 0}).find("s2 must be > 0"), std::string::npos);
    EXPECT_NE(message({25, 50, 1, 1, 0}).find("G1 must differ from 1"), std::string::npos);
    EXPECT_NE(message({25, 50, 1, 0.5, 0.5}).find("G1 must differ from Ginf"), std::string::npos);
    EXPECT_NE(message({NAN, 50, 1, 1.1, 0}).find("s1 must be a finite number"), std::string::npos);
    EXPECT_NE(message({25, INFINITY, 1, 1.1, 0}).find("s2 must be a finite number"), std::string::npos);
    EXPECT_NE(message({25, 50, 1, 1.1, NAN}).find("Ginf must be a finite number"), std::string::npos);
}

// PAPER-NOTES section 4: members of the section 4.1 families whose denominator has a root
// on s >= 0.
TEST(TransferFunction, RefusesUnstableDesignsAndNamesTheRoot) {
    for (const SecondOrderSpec& s : {SecondOrderSpec{25, 10, 1, 3, 0}, SecondOrderSpec{10, 25, 0.5, 3, 2}}) {
        try {
            design_second_order(s);
            FAIL() << "accepted an unstable filter " << name_of(s);
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("unstable filter"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("root at s ="), std::string::npos) << e.what();
        }
    }
    // The roots named in PAPER-NOTES: 18.0 and 52.0; 2.0 and 20.1.
    const SecondOrderSpec hp{25, 10, 1, 3, 0};
    const double r01 = (hp.G0 - hp.G1) / (1 - hp.G1);
    const double a2 = -(hp.G0 - hp.G1) / (hp.G1 - hp.Ginf) / (hp.s1 * hp.s1);
    const double a1 = -r01 * 2 / hp.s1 - (1 - hp.G0) / (1 - hp.G1) / hp.s2 - a2 * (1 - hp.Ginf) / (1 - hp.G1) * hp.s2;
    const auto roots = quadratic_roots(1, a1, a2);
    ASSERT_EQ(roots.size(), 2u);
    EXPECT_NEAR(roots[0].real(), 18.0, 0.1);
    EXPECT_NEAR(roots[1].real(), 52.0, 0.1);
}

// PAPER-NOTES section 3: Fig. 1's parameters peak at G(33.3) = -2.57, past G1 = 2, and flip sign.
TEST(TransferFunction, ReportsOvershootAndSignChange) {
    const TransferFunction g = design_second_order({20, 25, 1, 2, 0});
    const ResponseReport r = analyse_response(g, 2, 0.01, 1e5);
    EXPECT_NEAR(r.peak_gain, 2.57, 0.01);
    EXPECT_NEAR(r.peak_frequency, 33.3, 0.3);
    EXPECT_TRUE(r.changes_sign);
    EXPECT_NEAR(r.min_gain, -2.57, 0.01);
    ASSERT_EQ(r.warnings.size(), 2u);
    EXPECT_NE(r.warnings[0].find("overshoots"), std::string::npos);
    EXPECT_NE(r.warnings[1].find("changes sign"), std::string::npos);

    const ResponseReport clean = analyse_response(design_second_order({25, 50, 1, 1.1, 0}), 1.1, 0.01, 1e5);
    EXPECT_NEAR(clean.peak_gain, 1.1, 1e-4);
    EXPECT_NEAR(clean.peak_frequency, 25, 0.2);
    EXPECT_FALSE(clean.changes_sign);
    EXPECT_TRUE(clean.warnings.empty());
}

TEST(TransferFunction, QuadraticRootsAreAccurateWithoutCancellation) {
    // 1e-8 s^2 + s + 1: roots near -1 and -1e8; the naive formula loses the small one.
    const auto r = quadratic_roots(1, 1, 1e-8);
    ASSERT_EQ(r.size(), 2u);
    EXPECT_NEAR(r[1].real(), -1.00000001, 1e-12);
    EXPECT_NEAR(r[0].real(), -99999999.0, 1e-3);
}
