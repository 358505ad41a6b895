#include "core/design/transfer_function.h"
#include "reference_design.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <vector>

using namespace geofilter;

namespace {

// docs/paper-notes.md §9: every parameter set of the paper's figures.
const SecondOrderSpec paper_sets[] = {
    {20, 25, 1, 2, 0},      {20, 25, 1, 2, 0.9},    {10, 25, 1, 30, 0},      {630, 1260, 1, 3, 0.9},
    {630, 1260, 1, 0.01, 1.1}, {25, 60, 1, 3, 0},   {25, 60, 1, 3, 0.9},     {60, 120, 1, 2, 0.9},
    {25, 50, 1, 1.1, 0},    {200, 1000, 0.5, 1.1, 0}, {25, 400, 0.5, 1.1, 0.5},
};

std::string name_of(const SecondOrderSpec& s) {
    return "s1=" + format_number(s.s1) + " s2=" + format_number(s.s2) + " G0=" + format_number(s.G0) +
           " G1=" + format_number(s.G1) + " Ginf=" + format_number(s.Ginf);
}

} // namespace

// docs/paper-notes.md §2: G(0) = G0, G(s1) = G1, G'(s1) = 0, G(s2) = 1, G(inf) = Ginf.
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

// The core's closed form against the five conditions solved as a linear system
// (tests/support/reference_design): same six coefficients, for the paper's sets and for the
// stable members of a grid of further parameters (design_coefficients refuses the others).
TEST(TransferFunction, ClosedFormEqualsTheLinearSystemOfTheFiveConditions) {
    std::vector<SecondOrderSpec> specs(std::begin(paper_sets), std::end(paper_sets));
    for (double s2_over_s1 : {0.3, 2.0, 40.0})
        for (double G0 : {0.0, 0.5, 1.0})
            for (double G1 : {0.01, 0.5, 3.0, 30.0})
                for (double Ginf : {0.0, 0.9, 2.0})
                    if (G1 != Ginf) specs.push_back({7.0, 7.0 * s2_over_s1, G0, G1, Ginf});
    int compared = 0;
    for (const auto& spec : specs) {
        SCOPED_TRACE(name_of(spec));
        SecondOrderCoefficients c{};
        try {
            c = design_coefficients(spec);
        } catch (const Error&) {
            continue;  // unstable: RefusesUnstableDesignsAndNamesTheRoot covers refusals
        }
        ++compared;
        const reference::Eq15Reference r = reference::eq15_reference(spec.s1, spec.s2, spec.G0, spec.G1, spec.Ginf);
        // Each coefficient times the matching power of s1 is O(1) (or O(G1)): compare on that scale.
        const double scale = std::max({1.0, std::abs(spec.G1), std::abs(spec.Ginf)}) * 1e-9;
        EXPECT_NEAR(c.a0, r.a0, scale);
        EXPECT_NEAR(c.a1 * spec.s1, r.a1 * spec.s1, scale * std::max(1.0, std::abs(r.a1 * spec.s1)));
        EXPECT_NEAR(c.a2 * spec.s1 * spec.s1, r.a2 * spec.s1 * spec.s1, scale * std::max(1.0, std::abs(r.a2 * spec.s1 * spec.s1)));
        EXPECT_NEAR(c.b0, r.b0, scale);
        EXPECT_NEAR(c.b1 * spec.s1, r.b1 * spec.s1, scale * std::max(1.0, std::abs(r.b1 * spec.s1)));
        EXPECT_NEAR(c.b2 * spec.s1 * spec.s1, r.b2 * spec.s1 * spec.s1, scale * std::max(1.0, std::abs(r.b2 * spec.s1 * spec.s1)));
    }
    EXPECT_GT(compared, 40) << "too few stable parameter sets to compare";
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

// docs/paper-notes.md §4: members of the section 4.1 families whose denominator has a root
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
    // The roots named in docs/paper-notes.md §4: 18.0 and 52.0; 2.0 and 20.1.
    // The denominator comes from the test reference (the five conditions solved as a linear
    // system), not from the closed form being tested.
    const SecondOrderSpec hp{25, 10, 1, 3, 0};
    const reference::Eq15Reference ref = reference::eq15_reference(hp.s1, hp.s2, hp.G0, hp.G1, hp.Ginf);
    const auto roots = quadratic_roots(ref.a0, ref.a1, ref.a2);
    ASSERT_EQ(roots.size(), 2u);
    EXPECT_NEAR(roots[0].real(), 18.0, 0.1);
    EXPECT_NEAR(roots[1].real(), 52.0, 0.1);
}

// docs/paper-notes.md §3: Fig. 1's parameters peak at G(33.3) = -2.57, past G1 = 2, and flip sign.
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
