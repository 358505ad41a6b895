#include "filter_table.h"
#include "run_filter.h"
#include "core/denoise.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <complex>
#include <iterator>
#include <set>

#include "shapes.h"

using namespace geofilter;

namespace {
double reference_mean_radius(const Points& p) { return p.rowwise().norm().mean(); }
} // namespace

TEST(FilterTable, NamesAreTheOnesScriptsDependOn) {
    const std::set<std::string> expected = {"GeoFilter: Lowpass", "GeoFilter: Bandpass", "GeoFilter: Highpass",
                                            "GeoFilter: Notch", "GeoFilter: Band Exaggeration", "GeoFilter: Custom",
                                            "GeoFilter: Measure Selected Feature", "GeoFilter: Pole-Zero",
                                            "GeoFilter: Butterworth Lowpass", "GeoFilter: Denoise"};
    std::set<std::string> names, python, cli;
    for (const auto& f : filter_table()) {
        names.insert(f.name);
        python.insert(f.python_name);
        cli.insert(f.cli_name);
        EXPECT_EQ(find_filter(f.python_name), &f);
        EXPECT_EQ(find_filter(f.cli_name), &f);
    }
    EXPECT_EQ(names, expected);
    EXPECT_EQ(python.size(), expected.size());
    EXPECT_EQ(cli.size(), expected.size());
}

// Every preset default must pass the stability check (docs/paper-notes.md §4) and mean
// what its name says.
TEST(FilterTable, EverySecondOrderPresetIsStableAndHasTheFiveParameters) {
    for (const auto& f : filter_table()) {
        if (f.kind != FilterKind::SecondOrder) continue;
        SCOPED_TRACE(f.name);
        for (const char* p : {"s1", "s2", "G0", "G1", "Ginf", "useSelection", "featureShape", "solver"})
            ASSERT_NE(f.parameter(p), nullptr) << p;
        const SecondOrderSpec s{f.parameter("s1")->default_value, f.parameter("s2")->default_value,
                                f.parameter("G0")->default_value, f.parameter("G1")->default_value,
                                f.parameter("Ginf")->default_value};
        const TransferFunction g = design_second_order(s);
        for (const auto& pole : g.poles) EXPECT_TRUE(pole.imag() != 0 || pole.real() < 0);
    }
    auto gain = [](const char* name, double s) {
        const FilterSpec& f = *find_filter(name);
        std::vector<std::string> log;
        return design_from_values(f, default_values(f, false), nullptr, log, nullptr)(s);
    };
    EXPECT_LT(gain("lowpass", 1e4), 0.01);
    EXPECT_NEAR(gain("lowpass", 0), 1, 1e-12);
    EXPECT_LT(gain("highpass", 0.01), 0.01);
    EXPECT_NEAR(gain("highpass", 1e7), 1, 1e-3);
    EXPECT_LT(gain("bandpass", 0), 1e-12);
    EXPECT_LT(gain("notch", 630), 0.02);
    EXPECT_GT(gain("exaggerate", 25), 2.9);
}

// README and docs/paper-notes.md §4: the Highpass preset's poles are real and negative (two
// exact solves), every other second-order preset has one complex pair.
TEST(FilterTable, HighpassPolesAreRealTheOtherPresetsHaveAComplexPair) {
    for (const auto& f : filter_table()) {
        if (f.kind != FilterKind::SecondOrder) continue;
        SCOPED_TRACE(f.name);
        std::vector<std::string> log;
        const TransferFunction g = design_from_values(f, default_values(f, false), nullptr, log, nullptr);
        ASSERT_EQ(g.poles.size(), 2u);
        if (f.name == "GeoFilter: Highpass") {
            for (const auto& pole : g.poles) EXPECT_EQ(pole.imag(), 0);
            std::vector<double> re{g.poles[0].real(), g.poles[1].real()};
            std::sort(re.begin(), re.end());
            EXPECT_NEAR(re[0], -157.88, 0.01);
            EXPECT_NEAR(re[1], -5.758, 0.001);
        } else {
            EXPECT_NE(g.poles[0].imag(), 0);
            EXPECT_LT(std::abs(g.poles[1] - std::conj(g.poles[0])), 1e-9 * std::abs(g.poles[0]));
        }
    }
}

TEST(FilterTable, UseSelectionDefaultFollowsTheSelection) {
    const FilterSpec& f = *find_filter("lowpass");
    EXPECT_EQ(default_values(f, true).at("useSelection"), 1);
    EXPECT_EQ(default_values(f, false).at("useSelection"), 0);
}

TEST(FilterTable, FeatureFrequencyDrivesS1AndKeepsTheRatio) {
    const FilterSpec& f = *find_filter("notch");
    FeatureEllipsoid e;
    e.radius = 0.1;
    std::vector<std::string> log;
    double s1 = 0;
    ParameterValues v = default_values(f, true);
    const TransferFunction g = design_from_values(f, v, &e, log, &s1);
    EXPECT_NEAR(s1, 200, 1e-9);
    EXPECT_NEAR(g(400), 1.0, 1e-9);  // s2 = 2 s1 as in the preset's 630 / 1260
    v["featureShape"] = 1;
    design_from_values(f, v, &e, log, &s1);
    EXPECT_NEAR(s1, 100, 1e-9);
}

namespace {
bool logged(const std::vector<std::string>& log, const std::string& text) {
    for (const auto& line : log)
        if (line.find(text) != std::string::npos) return true;
    return false;
}
} // namespace

TEST(FilterTable, ButterworthCutoffFromValuesOrSelectionAndOrderChecked) {
    const FilterSpec& f = *find_filter("butterworth");
    EXPECT_EQ(f.python_name, "apply_geofilter_butterworth_lowpass");
    ParameterValues v = default_values(f, false);
    EXPECT_EQ(v.at("order"), 4);
    v["cutoff"] = 80;
    std::vector<std::string> log;
    double sc = 0;
    TransferFunction g = design_from_values(f, v, nullptr, log, &sc);
    EXPECT_EQ(sc, 80);
    EXPECT_NEAR(g(80), 0.5, 1e-12);
    EXPECT_NEAR(g(160), 1 / 17.0, 1e-12);  // 1 / (1 + 2^4)
    EXPECT_TRUE(logged(log, "operator cotangent"));
    FeatureEllipsoid e;
    e.radius = 0.1;
    g = design_from_values(f, v, &e, log, &sc);
    EXPECT_NEAR(sc, 200, 1e-9);
    for (double bad : {0.0, 9.0, 2.5}) {
        v["order"] = bad;
        try {
            design_from_values(f, v, nullptr, log);
            ADD_FAILURE() << "order " << bad << " accepted";
        } catch (const Error& err) {
            EXPECT_NE(std::string(err.what()).find("order"), std::string::npos);
        }
    }
}

TEST(FilterTable, DenoiseCutsAtTwiceTheSelectedBumpAndHasNoDesignWithoutOne) {
    const FilterSpec& f = *find_filter("denoise");
    EXPECT_EQ(f.name, "GeoFilter: Denoise");
    EXPECT_EQ(f.python_name, "apply_geofilter_denoise");
    const ParameterValues v = default_values(f, true);
    FeatureEllipsoid bump;
    bump.radius = 0.05;
    std::vector<std::string> log;
    double sc = 0;
    TransferFunction g = design_from_values(f, v, &bump, log, &sc);
    EXPECT_NEAR(sc, 2 / (0.1 * 0.1), 1e-9);  // cutoff radius 2 r
    EXPECT_EQ(g.poles.size(), 4u);
    EXPECT_EQ(operator_from_values(f, v, true), Operator::Cotangent);
    EXPECT_TRUE(logged(log, "selected bump"));
    // Without a bump the design is made on the mesh (by estimated risk), on either operator.
    EXPECT_THROW(design_from_values(f, default_values(f, false), nullptr, log, &sc), Error);
    EXPECT_FALSE(operator_from_values(f, default_values(f, false), false).has_value());
}

TEST(FilterTable, DenoiseRunLogsOperatorOrderAndCutoff) {
    const Mesh m = icosphere(3, 1.0);
    const FilterSpec& f = *find_filter("denoise");
    const std::vector<int> none;
    const RunOutput out = run_filter(f, default_values(f, false), {m.points, m.triangles, none, {}});
    EXPECT_TRUE(logged(out.log, "Butterworth lowpass of order 4"));
    const std::size_t candidates = std::size(denoise_umbrella_cutoffs) + std::size(denoise_cutoff_radii);
    EXPECT_TRUE(logged(out.log, "of " + std::to_string(candidates) +
                                    " lowpasses scored, each operator's cutoffs searched downhill"));
    EXPECT_TRUE(logged(out.log, "<- chosen"));
    // A clean sphere is all low frequency: whichever lowpass is chosen, its radius barely changes.
    EXPECT_NEAR(reference_mean_radius(out.points), 1.0, 2e-3);
}
