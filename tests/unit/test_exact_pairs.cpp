// Complex pole pairs solved exactly (a factorisation of Kt - r I, MUMPS's complex LDL^T)
// where CG on them is predicted to cost more: the result must be the dense spectral filter's
// to the tolerance, the cost rule must keep cheap pairs on CG, and a factorisation that is
// refused or fails must leave the pair to CG with the same accuracy, saying why.
#include "core/design/butterworth.h"
#include "core/filter/filter.h"
#include "core/solve/mixed_precision_factor.h"
#include "exact_pairs.h"
#include "real_mesh.h"
#include "spectral.h"

#include <gtest/gtest.h>

using namespace geofilter;
using namespace geofilter::reference;

namespace {

FilterOptions with_exact_pairs(double tolerance = 1e-7) {
    FilterOptions options;
    options.tolerance = tolerance;
    options.complex_factorization = exact_pair_factorization();
    return options;
}

// The area-weighted RMS distance of `out` from the dense spectral filter's result.
double spectral_error(const Mesh& m, const Spectrum& spectrum, const TransferFunction& g, const Points& out) {
    return area_weighted_rms(out - spectral_filter(spectrum, m.points, g), spectrum.mass);
}

// A factorisation that never gets to factorise: too big for any machine, or failing.
class RefusedFactor : public ComplexShiftedFactor {
public:
    explicit RefusedFactor(bool fails) : fails_(fails) {}
    std::string name() const override { return "a refused factor"; }
    double estimated_factorization_bytes() const override { return fails_ ? 0 : 1e30; }
    void factorize(std::complex<double>) override {
        if (fails_) throw Error("the factor library failed");
        ADD_FAILURE() << "factorised despite needing more memory than there is";
    }
    bool holds(std::complex<double>) const override { return false; }
    Eigen::MatrixXcd solve(const Eigen::MatrixXcd& b) override { return b; }

private:
    bool fails_;
};

// Another factor's solves times `scale`, under its own name: scale 1.5 makes a factor whose
// every refinement only halves the error, which a single-precision factor too imprecise for
// the pole would look like.
class ScaledFactor : public ComplexShiftedFactor {
public:
    ScaledFactor(std::unique_ptr<ComplexShiftedFactor> inner, double scale, std::string name)
        : inner_(std::move(inner)), scale_(scale), name_(std::move(name)) {}
    std::string name() const override { return name_; }
    double estimated_factorization_bytes() const override { return inner_->estimated_factorization_bytes(); }
    void factorize(std::complex<double> r) override { inner_->factorize(r); }
    bool holds(std::complex<double> r) const override { return inner_->holds(r); }
    Eigen::MatrixXcd solve(const Eigen::MatrixXcd& b) override { return scale_ * inner_->solve(b); }

private:
    std::unique_ptr<ComplexShiftedFactor> inner_;
    double scale_;
    std::string name_;
};

// The patch's dense spectrum, computed once for the tests that need it (seconds under ASan).
const Spectrum& man_patch_spectrum() {
    static const Spectrum spectrum = spectrum_of(man_scan_patch());
    return spectrum;
}

} // namespace

#ifdef GEOFILTER_EXACT_PAIRS
TEST(ExactPairs, BuiltWithMumps) { EXPECT_TRUE(exact_pair_factorization()); }
#else
TEST(ExactPairs, BuiltWithoutMumpsEveryPairGoesToCg) { EXPECT_FALSE(exact_pair_factorization()); }
#endif

TEST(ExactPairs, SharpResonancesOnARealScanAreSolvedExactlyToTheTolerance) {
    if (!exact_pair_factorization()) GTEST_SKIP() << "configured with GEOFILTER_EXACT_PAIRS=OFF";
    const Mesh& m = man_scan_patch();
    const Spectrum& spectrum = man_patch_spectrum();
    const double diag = bbox_diagonal(m.points);
    const std::vector<SecondOrderSpec> sharp = {
        {630, 1260, 1, 0.01, 1.1},  // notch (Fig. 9)
        {25, 60, 1, 3, 0.9},        // band exaggeration (Fig. 10)
        {200, 300, 1, 6, 0.5},      // a sharper exaggeration
    };
    for (const SecondOrderSpec& spec : sharp)
        for (double tolerance : {1e-5, 1e-9}) {
            SCOPED_TRACE("s1 = " + format_number(spec.s1) + ", G1 = " + format_number(spec.G1) + ", tolerance " +
                         format_number(tolerance));
            const TransferFunction g = design_second_order(spec);
            FilterReport report;
            const Points out = apply_filter(m.points, m.triangles, g, with_exact_pairs(tolerance), &report);
            EXPECT_EQ(report.exact_pairs, 1) << report.exact_pair_note;
            EXPECT_EQ(report.iterations, 0);
            EXPECT_LE(area_weighted_rms(out - spectral_filter(spectrum, m.points, g), spectrum.mass), tolerance * diag);
        }
}

TEST(ExactPairs, ACascadeSharingOneRealFactorStaysOnCgAndMatchesTheSpectralFilter) {
    if (!exact_pair_factorization()) GTEST_SKIP() << "configured with GEOFILTER_EXACT_PAIRS=OFF";
    const Mesh& m = man_scan_patch();
    const Spectrum& spectrum = man_patch_spectrum();
    // Order 8 in s: four pairs on the circle |r| = 400, the sharpest alone worth an exact
    // solve, but the other three need the real factor at that shift anyway.
    const TransferFunction g = design_butterworth_lowpass(400, 8);
    FilterReport report;
    const Points out = apply_filter(m.points, m.triangles, g, with_exact_pairs(), &report);
    EXPECT_EQ(report.exact_pairs, 0);
    EXPECT_TRUE(report.exact_pair_note.empty());
    EXPECT_GT(report.iterations, 0);
    EXPECT_LE(spectral_error(m, spectrum, g, out), 1e-7 * bbox_diagonal(m.points));
}

TEST(ExactPairs, TheLowpassPairAloneIsSolvedExactly) {
    // One pair and no other pole: the real factor CG would need costs more than the exact
    // pair's single-precision factor and its refined solves (exact_pair.h's measured costs).
    if (!exact_pair_factorization()) GTEST_SKIP() << "configured with GEOFILTER_EXACT_PAIRS=OFF";
    const Mesh m = wavy_sheet(30);
    const Spectrum spectrum = spectrum_of(m);
    const TransferFunction g = design_second_order({25, 50, 1, 1.1, 0});
    FilterReport report;
    const Points out = apply_filter(m.points, m.triangles, g, with_exact_pairs(), &report);
    EXPECT_EQ(report.exact_pairs, 1) << report.exact_pair_note;
    EXPECT_EQ(report.iterations, 0);
    EXPECT_LE(spectral_error(m, spectrum, g, out), 1e-7 * bbox_diagonal(m.points));
}

TEST(ExactPairs, InAPreviewSessionTheLowpassKeepsARealFactorForTheNextChange) {
    // With a FilterCache the next parameter change reuses a real factor at a nearby shift;
    // a complex factor would have to be made again. The notch still goes exact.
    if (!exact_pair_factorization()) GTEST_SKIP() << "configured with GEOFILTER_EXACT_PAIRS=OFF";
    const Mesh m = wavy_sheet(30);
    const Spectrum spectrum = spectrum_of(m);
    FilterCache cache;
    FilterReport first, changed, notch;
    apply_filter(m.points, m.triangles, design_second_order({25, 50, 1, 1.1, 0}), with_exact_pairs(), &first, &cache);
    const TransferFunction g = design_second_order({27.5, 55, 1, 1.1, 0});
    const Points out = apply_filter(m.points, m.triangles, g, with_exact_pairs(), &changed, &cache);
    EXPECT_EQ(first.exact_pairs, 0);
    EXPECT_EQ(changed.exact_pairs, 0);
    EXPECT_EQ(changed.seconds_factorization, 0) << "the change should reuse the held factor";
    EXPECT_LE(spectral_error(m, spectrum, g, out), 1e-7 * bbox_diagonal(m.points));
    FilterCache other;
    apply_filter(m.points, m.triangles, design_second_order({630, 1260, 1, 0.01, 1.1}), with_exact_pairs(), &notch, &other);
    EXPECT_EQ(notch.exact_pairs, 1) << notch.exact_pair_note;
}

TEST(ExactPairs, ARefusedOrFailingFactorisationLeavesThePairToCgAndSaysWhy) {
    const Mesh m = wavy_sheet(30);
    const Spectrum spectrum = spectrum_of(m);
    const TransferFunction notch = design_second_order({630, 1260, 1, 0.01, 1.1});
    const Points exact = spectral_filter(spectrum, m.points, notch);
    for (bool fails : {false, true}) {
        SCOPED_TRACE(fails ? "factorisation fails" : "too big");
        FilterOptions options;
        options.complex_factorization = [fails](const SparseMatrix&) { return std::make_unique<RefusedFactor>(fails); };
        FilterReport report, again;
        FilterCache cache;
        const Points out = apply_filter(m.points, m.triangles, notch, options, &report, &cache);
        // A second run on the same mesh does not try again, and still says why.
        apply_filter(m.points, m.triangles, design_second_order({600, 1200, 1, 0.01, 1.1}), options, &again, &cache);
        EXPECT_EQ(again.exact_pairs, 0);
        EXPECT_EQ(again.exact_pair_note, report.exact_pair_note);
        EXPECT_EQ(report.exact_pairs, 0);
        EXPECT_GT(report.iterations, 0);
        EXPECT_NE(report.exact_pair_note.find(fails ? "the factor library failed" : "MiB are available"), std::string::npos)
            << report.exact_pair_note;
        EXPECT_NE(solver_used(report).find(report.exact_pair_note), std::string::npos);
        EXPECT_LE(area_weighted_rms(out - exact, spectrum.mass), 1e-7 * bbox_diagonal(m.points));
    }
}

TEST(ExactPairs, AFilterCacheKeepsTheComplexFactorForTheSameFilter) {
    if (!exact_pair_factorization()) GTEST_SKIP() << "configured with GEOFILTER_EXACT_PAIRS=OFF";
    const Mesh m = wavy_sheet(30);
    FilterCache cache;
    const TransferFunction notch = design_second_order({630, 1260, 1, 0.01, 1.1});
    FilterReport first, second;
    const Points a = apply_filter(m.points, m.triangles, notch, with_exact_pairs(1e-7), &first, &cache);
    // Another tolerance: not the held result, but the held factor of the same pair.
    const Points b = apply_filter(m.points, m.triangles, notch, with_exact_pairs(1e-9), &second, &cache);
    EXPECT_EQ(first.exact_pairs, 1);
    EXPECT_EQ(second.exact_pairs, 1);
    EXPECT_GT(first.seconds_factorization, 0);
    EXPECT_EQ(second.seconds_factorization, 0);
    EXPECT_LE((a - b).cwiseAbs().maxCoeff(), 1e-6 * bbox_diagonal(m.points));
}

TEST(ExactPairs, TheSinglePrecisionFactorIsRefinedInDoubleToTheTolerance) {
    if (!exact_pair_factorization()) GTEST_SKIP() << "configured with GEOFILTER_EXACT_PAIRS=OFF";
    const Mesh& m = man_scan_patch();
    const Spectrum& spectrum = man_patch_spectrum();
    const TransferFunction notch = design_second_order({630, 1260, 1, 0.01, 1.1});
    // Far below what single precision alone resolves (~1e-7 of the solution's size at best).
    const double tolerance = 1e-11;
    FilterReport report;
    const Points out = apply_filter(m.points, m.triangles, notch, with_exact_pairs(tolerance), &report);
    EXPECT_EQ(report.exact_pairs, 1) << report.exact_pair_note;
    EXPECT_NE(report.exact_pair_method.find("single precision"), std::string::npos) << report.exact_pair_method;
    EXPECT_GE(report.exact_pair_refinements, 1);
    EXPECT_LE(area_weighted_rms(out - spectral_filter(spectrum, m.points, notch), spectrum.mass),
              tolerance * bbox_diagonal(m.points));
}

TEST(ExactPairs, AFactorTooImpreciseToRefineIsReplacedByADoublePrecisionOneOrLeftToCg) {
    if (!exact_pair_factorization()) GTEST_SKIP() << "configured with GEOFILTER_EXACT_PAIRS=OFF";
    const Mesh m = wavy_sheet(30);
    const Spectrum spectrum = spectrum_of(m);
    const TransferFunction notch = design_second_order({630, 1260, 1, 0.01, 1.1});
    const Points exact = spectral_filter(spectrum, m.points, notch);
    for (bool can_raise : {true, false}) {
        SCOPED_TRACE(can_raise ? "a double-precision factor to fall back on" : "none");
        FilterOptions options = with_exact_pairs(1e-9);
        options.complex_factorization = [can_raise](const SparseMatrix& kt) {
            MixedPrecisionFactor::Make precise;
            if (can_raise)
                precise = [&kt] { return std::make_unique<ScaledFactor>(exact_pair_factorization()(kt), 1.0, "precise"); };
            return std::make_unique<MixedPrecisionFactor>(
                [&kt] { return std::make_unique<ScaledFactor>(exact_pair_factorization()(kt), 1.5, "imprecise"); },
                precise);
        };
        FilterReport report;
        const Points out = apply_filter(m.points, m.triangles, notch, options, &report);
        if (can_raise) {
            EXPECT_EQ(report.exact_pairs, 1) << report.exact_pair_note;
            EXPECT_EQ(report.exact_pair_method, "precise");
            EXPECT_EQ(report.iterations, 0);
        } else {
            EXPECT_EQ(report.exact_pairs, 0);
            EXPECT_NE(report.exact_pair_note.find("error bound stayed"), std::string::npos) << report.exact_pair_note;
            EXPECT_GT(report.iterations, 0);
        }
        EXPECT_LE(area_weighted_rms(out - exact, spectrum.mass), 1e-9 * bbox_diagonal(m.points));
    }
}
