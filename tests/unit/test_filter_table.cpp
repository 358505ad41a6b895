#include "filter_table.h"
#include "run_filter.h"
#include "core/denoise/denoise.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <complex>
#include <iterator>
#include <set>

#include "shapes.h"

using namespace geofilter;

namespace {
double reference_mean_radius(const Points& p) { return p.rowwise().norm().mean(); }

// A second-order preset's values with its reference frequencies typed.
ParameterValues reference_values(const FilterSpec& f) {
    ParameterValues v = default_values(f, false);
    v[param::s1] = f.reference.s1;
    v[param::s2] = f.reference.s2;
    return v;
}
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
        // The gains are the dialog's defaults; the reference frequencies are the paper's.
        EXPECT_EQ(f.parameter("G0")->default_value, f.reference.G0);
        EXPECT_EQ(f.parameter("G1")->default_value, f.reference.G1);
        EXPECT_EQ(f.parameter("Ginf")->default_value, f.reference.Ginf);
        const SecondOrderSpec s = f.reference;
        const TransferFunction g = design_second_order(s);
        for (const auto& pole : g.poles) EXPECT_TRUE(pole.imag() != 0 || pole.real() < 0);
    }
    auto gain = [](const char* name, double s) {
        const FilterSpec& f = *find_filter(name);
        std::vector<std::string> log;
        return design_from_values(f, reference_values(f), nullptr, log, nullptr)(s);
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
        const TransferFunction g = design_from_values(f, reference_values(f), nullptr, log, nullptr);
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

// The dialog speaks in sizes: every filter a user sets by size opens on the feature radius,
// a length (MeshLab's RichAbsPerc) whose default is a fraction of the diagonal.
TEST(FilterTable, SizedFiltersOpenOnTheFeatureRadiusAndLengthsAreLengths) {
    for (const auto& f : filter_table()) {
        SCOPED_TRACE(f.name);
        if (const ParameterSpec* b = f.parameter(param::blend_width)) EXPECT_EQ(b->type, ParameterType::Length);
        if (f.kind == FilterKind::Measure || f.kind == FilterKind::Denoise) {
            EXPECT_EQ(f.parameter(param::radius), nullptr);
            continue;
        }
        ASSERT_FALSE(f.parameters.empty());
        EXPECT_EQ(f.parameters.front().name, param::radius) << "meshlabserver fills in only the first parameter a script omits";
        EXPECT_EQ(f.parameters.front().type, ParameterType::Length);
        const double fraction = f.parameters.front().default_value;
        if (f.kind == FilterKind::PoleZero) EXPECT_EQ(fraction, 0) << "0 = the corners as typed";
        else EXPECT_TRUE(fraction > 0.005 && fraction < 0.2) << fraction;
    }
}

// A preset left at its defaults designs s1 = 2/r^2 from r = fraction x diagonal, so the same
// mesh scaled by 1000 is filtered into the same shape scaled by 1000.
TEST(FilterTable, TheDefaultRadiusScalesWithTheMesh) {
    const Mesh m = icosphere(3, 1.0);
    Points bumpy = m.points;
    for (Eigen::Index i = 0; i < bumpy.rows(); ++i) bumpy.row(i) *= 1 + 0.05 * std::sin(7 * bumpy(i, 0)) * std::cos(5 * bumpy(i, 1));
    const std::vector<int> none;
    for (const char* name : {"lowpass", "notch", "exaggerate", "butterworth"}) {
        SCOPED_TRACE(name);
        const FilterSpec& f = *find_filter(name);
        const RunOutput small = run_filter(f, default_values(f, false), {bumpy, m.triangles, none, {}});
        const Points big_input = 1000 * bumpy;
        const RunOutput big = run_filter(f, default_values(f, false), {big_input, m.triangles, none, {}});
        const double r = f.parameter(param::radius)->default_value * bounding_box_diagonal(bumpy);
        EXPECT_NEAR(small.s1_used, 2 / (r * r), 1e-9 * small.s1_used);
        EXPECT_NEAR(big.s1_used * 1e6, small.s1_used, 1e-9 * small.s1_used);
        EXPECT_EQ(small.radius_used, r);
        const double size = bounding_box_diagonal(big_input);
        EXPECT_LT((big.points - 1000 * small.points).cwiseAbs().maxCoeff(), 1e-6 * size);
        EXPECT_GT((small.points - bumpy).cwiseAbs().maxCoeff(), 1e-3) << "the default filter does something";
    }
}

// The radius is the paper's frequency in other words: a radius r gives the design typed as
// s1 = 2/r^2 (1/r^2 cylinder-like) with the preset's ratio s2/s1.
TEST(FilterTable, ARadiusGivesTheDesignOfItsFrequency) {
    for (const auto& f : filter_table()) {
        if (f.kind != FilterKind::SecondOrder) continue;
        SCOPED_TRACE(f.name);
        for (const double shape : {0.0, 1.0}) {
            ParameterValues sized = default_values(f, false);
            sized[param::radius] = 0.3;
            sized[param::feature_shape] = shape;
            ParameterValues typed = sized;
            typed[param::s1] = (shape == 0 ? 2 : 1) / (0.3 * 0.3);
            typed[param::s2] = typed[param::s1] * f.reference.s2 / f.reference.s1;
            std::vector<std::string> log;
            const TransferFunction a = design_from_values(f, sized, nullptr, log), b = design_from_values(f, typed, nullptr, log);
            for (const double s : {0.5, 5.0, 22.2, 50.0, 500.0}) EXPECT_NEAR(a(s), b(s), 1e-12 * (1 + std::abs(b(s))));
        }
    }
    const FilterSpec& f = *find_filter("lowpass");
    ParameterValues v = default_values(f, false, 1.0);
    v[param::s2] = 50;
    std::vector<std::string> log;
    EXPECT_THROW(design_from_values(f, v, nullptr, log), Error) << "s2 typed without s1 is refused";
    v = default_values(f, false);
    EXPECT_THROW(design_from_values(f, v, nullptr, log), Error) << "no radius and no mesh: nothing to design from";
    v[param::radius] = -1;
    EXPECT_THROW(design_from_values(f, v, nullptr, log), Error);
}
