// Denoise with a selected bump removes the pattern of bumps like it. A sphere covered with
// bumps (or dents) against the bare sphere: a flat lowpass alone keeps the pattern's local
// mean height (the volume grows) and rounds the bumps' base; the fitted pattern, subtracted,
// takes the volume and the shape back to the bare sphere's. Checked against the bare sphere,
// never against the fit's own numbers.
#include "core/denoise/bump_pattern.h"
#include "core/denoise/denoise.h"
#include "core/denoise/normal_motion.h"
#include "core/design/butterworth.h"
#include "core/mesh/boundary.h"
#include "core/mesh/surface_measures.h"
#include "shapes.h"
#include "spectral.h"
#include "run_filter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace geofilter;
using geofilter::reference::rms_distance;

namespace {

double volume(const Points& p, const Triangles& t) {
    double v = 0;
    for (Eigen::Index f = 0; f < t.rows(); ++f)
        v += p.row(t(f, 0)).dot(p.row(t(f, 1)).cross(p.row(t(f, 2)))) / 6;
    return v;
}

double rms_radius_error(const Points& p) {
    return std::sqrt((p.rowwise().norm().array() - 1.0).square().mean());
}

struct BumpySphere {
    Mesh mesh;
    std::vector<int> one_bump;  // the faces within rho of the first bump's centre
};

enum class Profile { Gaussian, CosineCap };

// `side` +1: bumps, -1: dents; height 0.24 rho, as in docs/results.md section 4. Gaussian
// bumps exp(-(d/rho)^2), or cosine caps (1 + cos(pi d / (2 rho))) / 2 out to d = 2 rho, a
// profile the fit does not assume.
BumpySphere bumpy_sphere(int side, double rho, int count, Profile profile = Profile::Gaussian, int levels = 6) {
    BumpySphere out{icosphere(levels, 1.0), {}};
    std::mt19937 random(7);
    std::normal_distribution<double> gauss;
    std::vector<Eigen::RowVector3d> centres;
    // At least 1.6 rho apart, as in the comparison's patterns: closer, two bumps merge into
    // one peak, which a pattern of separate bumps does not describe.
    while (static_cast<int>(centres.size()) < count) {
        const Eigen::RowVector3d c = Eigen::RowVector3d(gauss(random), gauss(random), gauss(random)).normalized();
        if (std::all_of(centres.begin(), centres.end(), [&](const auto& o) { return (o - c).norm() >= 1.6 * rho; }))
            centres.push_back(c);
    }
    Points& p = out.mesh.points;
    for (Eigen::Index v = 0; v < p.rows(); ++v) {
        const Eigen::RowVector3d n = p.row(v).normalized();
        double h = 0;
        for (const auto& c : centres) {
            const double d = (n - c).norm();
            h += 0.24 * rho *
                 (profile == Profile::Gaussian ? std::exp(-d * d / (rho * rho))
                                               : (d < 2 * rho ? 0.5 * (1 + std::cos(M_PI * d / (2 * rho))) : 0.0));
        }
        p.row(v) = n * (1 + side * h);
    }
    for (Eigen::Index f = 0; f < out.mesh.triangles.rows(); ++f) {
        bool inside = true;
        for (int k = 0; k < 3; ++k)
            inside = inside && (p.row(out.mesh.triangles(f, k)).normalized() - centres[0]).norm() < rho;
        if (inside) out.one_bump.push_back(static_cast<int>(f));
    }
    return out;
}


const double bare_volume = volume(icosphere(6, 1.0).points, icosphere(6, 1.0).triangles);

struct Outcome {
    double volume_error, rms, lowpass_volume_error, lowpass_rms;
    RunOutput run;
};

Outcome denoise_selected(const BumpySphere& s) {
    const FilterSpec& spec = *find_filter("denoise");
    Outcome o{0, 0, 0, 0, run_filter(spec, default_values(spec, true), {s.mesh.points, s.mesh.triangles, s.one_bump, {}})};
    // The same Butterworth lowpass alone, for comparison.
    const Points lowpass = apply_filter(s.mesh.points, s.mesh.triangles, o.run.transfer);
    o.volume_error = std::abs(volume(o.run.points, s.mesh.triangles) - bare_volume) / bare_volume;
    o.lowpass_volume_error = std::abs(volume(lowpass, s.mesh.triangles) - bare_volume) / bare_volume;
    o.rms = rms_radius_error(o.run.points);
    o.lowpass_rms = rms_radius_error(lowpass);
    return o;
}

bool logged(const RunOutput& out, const std::string& text) {
    for (const auto& line : out.log)
        if (line.find(text) != std::string::npos) return true;
    return false;
}

// The flat fallback where the fit found no width narrower than the selection: the lowpass
// designed for the measured bump, its motion along the normals, with the base's detail that
// it removed put back (with_base_detail, checked against known fields in test_base_detail).
Points flat_lowpass_for_selection(const Points& points, const Triangles& triangles, const std::vector<int>& selected) {
    const FilterSpec& spec = *find_filter("denoise");
    const ParameterValues values = default_values(spec, true);
    const FeatureEllipsoid footprint = measure_feature(points, triangles, selected);
    const RunOutput cut = design_run(spec, values, footprint);
    FilterOptions options = filter_options(spec, values);
    options.op = cut.op;
    const Points flat = keep_normal_motion(points, apply_filter(points, triangles, cut.transfer, options), triangles);
    return with_base_detail(points, flat, triangles, selected, footprint.radius);
}

} // namespace

TEST(BumpPattern, DenoiseFromOneSelectedBumpRemovesThePatternAndItsVolume) {
    // 150 and 300 bumps at random places: at 300 their tails overlap everywhere and the
    // surface never shows the base between them.
    for (int count : {150, 300})
        for (int side : {1, -1}) {
            SCOPED_TRACE(std::to_string(count) + (side > 0 ? " bumps" : " dents"));
            const BumpySphere s = bumpy_sphere(side, 0.08, count);
            ASSERT_GT(s.one_bump.size(), 10u);
            ASSERT_GT(side * (volume(s.mesh.points, s.mesh.triangles) - bare_volume), 0.005 * bare_volume);
            const Outcome o = denoise_selected(s);
            EXPECT_GT(o.lowpass_volume_error, 0.005);  // the offset a flat lowpass keeps ...
            // ... gone to within the 0.3 % with 150 bumps (measured 0.13-0.16 %, the
            // lowpass 1.4 %); at 300, every bump crowded by its neighbours, 0.37-0.39 % remains
            // (the lowpass: 2.7-2.8 %).
            if (count == 150) EXPECT_LT(o.volume_error, 0.003);
            EXPECT_LT(o.volume_error, 0.2 * o.lowpass_volume_error);
            EXPECT_LT(o.rms, 0.3 * o.lowpass_rms);  // measured 0.18-0.20
            EXPECT_TRUE(logged(o.run, side > 0 ? "points outwards" : "points inwards"));
            EXPECT_TRUE(logged(o.run, "pattern of bumps removed"));
        }
}

TEST(BumpPattern, BumpsOfAnotherProfileAreStillMostlyRemoved) {
    // Cosine caps: the Gaussian profile is only an approximation of them. Measured: volume
    // 0.09 % off against 1.7 % for the lowpass, RMS 0.41 of the lowpass's.
    const BumpySphere s = bumpy_sphere(1, 0.08, 150, Profile::CosineCap);
    const Outcome o = denoise_selected(s);
    EXPECT_LT(o.volume_error, 0.2 * o.lowpass_volume_error);
    EXPECT_LT(o.rms, 0.5 * o.lowpass_rms);
}

TEST(BumpPattern, ASurfaceWhoseOwnDetailDominatesGetsTheFlatLowpass) {
    // Per-vertex noise as large as the "bump": no pattern explains the selection. Returning the
    // input would remove nothing the user asked to remove; the lowpass at the selected scale,
    // which does, is returned (its motion along the normals, as Denoise keeps it, with the
    // base's detail it removed put back: with_base_detail), and the warning says why. No
    // narrower width is fitted here, so the lowpass is cut for the selection.
    BumpySphere s = bumpy_sphere(1, 0.2, 1, Profile::Gaussian, 4);
    std::mt19937 random(3);
    std::normal_distribution<double> gauss(0.0, 0.01);
    for (Eigen::Index v = 0; v < s.mesh.points.rows(); ++v) s.mesh.points.row(v) *= 1 + gauss(random);
    const FilterSpec& spec = *find_filter("denoise");
    const ParameterValues values = default_values(spec, true);
    const RunOutput out = run_filter(spec, values, {s.mesh.points, s.mesh.triangles, s.one_bump, {}});
    EXPECT_EQ(out.points, flat_lowpass_for_selection(s.mesh.points, s.mesh.triangles, s.one_bump));
    EXPECT_NE(out.points, s.mesh.points);
    std::string log;
    for (const auto& line : out.log) log += line + "\n";
    EXPECT_TRUE(logged(out, "fell back to the flat lowpass because")) << log;
    EXPECT_TRUE(logged(out, "because the selected bump is not one of a pattern")) << log;
    EXPECT_FALSE(out.report.warnings.empty());
}

TEST(BumpPattern, AFlatLowpassThatWouldTakeTheSurfacesOwnPartsIsRefusedAndOnlyTheNoiseGoes) {
    // As above (noise as large as the bump: no pattern explains it), and the sphere carries
    // three narrow horns, features of the bump's own size that are no bumps of a pattern. The
    // flat lowpass at the bump's size would flatten them: its volume change, measured here
    // independently, is far above what a pattern's removal makes (which keeps the mean
    // height). Denoise removes nothing at the bump's size, says why, and takes the noise
    // off by the sampling-noise rule: closer to the noise-free surface, horns and volume kept.
    BumpySphere s = bumpy_sphere(1, 0.2, 1, Profile::Gaussian, 4);
    std::mt19937 random(3);
    std::normal_distribution<double> gauss(0.0, 0.01);
    const Eigen::RowVector3d bump_centre = s.mesh.points.row(s.mesh.triangles(s.one_bump[0], 0)).normalized();
    const std::vector<Eigen::RowVector3d> horns{-bump_centre, Eigen::RowVector3d(bump_centre[1], -bump_centre[0], 0).normalized(),
                                                Eigen::RowVector3d(-bump_centre[1], bump_centre[0], 0).normalized()};
    Points clean = s.mesh.points;
    for (Eigen::Index v = 0; v < s.mesh.points.rows(); ++v) {
        const Eigen::RowVector3d n = s.mesh.points.row(v).normalized();
        double horn = 0;
        for (const auto& c : horns) horn += 0.5 * std::exp(-(n - c).squaredNorm() / (0.15 * 0.15));
        clean.row(v) = s.mesh.points.row(v) + horn * n;
        s.mesh.points.row(v) = s.mesh.points.row(v) * (1 + gauss(random)) + horn * n;
    }
    const FilterSpec& spec = *find_filter("denoise");
    const ParameterValues values = default_values(spec, true);
    const RunOutput out = run_filter(spec, values, {s.mesh.points, s.mesh.triangles, s.one_bump, {}});
    std::string log;
    for (const auto& line : out.log) log += line + "\n";
    const RunOutput bump = design_run(spec, values, measure_feature(s.mesh.points, s.mesh.triangles, s.one_bump));
    FilterOptions options = filter_options(spec, values);
    options.op = bump.op;
    const Points flat = keep_normal_motion(s.mesh.points, apply_filter(s.mesh.points, s.mesh.triangles, bump.transfer, options),
                                           s.mesh.triangles);
    const double before = volume(s.mesh.points, s.mesh.triangles);
    EXPECT_GT(std::abs(volume(flat, s.mesh.triangles) - before) / before, denoise_flat_max_volume_change) << log;
    EXPECT_TRUE(logged(out, "would change the enclosed volume by")) << log;
    EXPECT_TRUE(logged(out, "per-vertex sampling noise is removed instead")) << log;
    EXPECT_FALSE(out.report.warnings.empty());
    auto rms = [&](const Points& p) { return std::sqrt((p - clean).rowwise().squaredNorm().mean()); };
    EXPECT_LT(rms(out.points), 0.8 * rms(s.mesh.points)) << log;
    const double truth = volume(clean, s.mesh.triangles);
    EXPECT_LT(std::abs(volume(out.points, s.mesh.triangles) - truth) / truth, denoise_flat_max_volume_change) << log;
}

TEST(BumpPattern, MotionAcrossTheSurfaceIsTheSamplingRulesLessItsPartAlongTheNormals) {
    // A flat square in the plane z = 0: the normals are +z, so of any motion only x and y are
    // added, whatever the sampled points' z.
    const Points input = (Points(4, 3) << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0).finished();
    const Triangles square = (Triangles(2, 3) << 0, 1, 2, 0, 2, 3).finished();
    Points denoised = input;
    denoised.col(2).setConstant(0.5);
    Points sampled = input;
    sampled.row(2) += Eigen::RowVector3d(0.1, -0.2, 0.3);
    const Points out = add_motion_across_surface(denoised, input, sampled, square);
    Points expected = denoised;
    expected.row(2) += Eigen::RowVector3d(0.1, -0.2, 0);
    EXPECT_LT((out - expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(BumpPattern, NoiseInRandomDirectionsAlsoLeavesAcrossTheSurface) {
    // Bumps on a sphere noised in random directions by 0.3 mean edge lengths: the selected
    // bump's path (here the flat lowpass) moves the vertices along the normals only: without
    // the sampling rule's motion across the surface the error in the truth's tangent planes
    // ended 1.33x the input's, with it 0.32x (the RMS distance 1.15x and 0.36x).
    BumpySphere s = bumpy_sphere(1, 0.2, 30, Profile::Gaussian, 4);
    const Points clean = s.mesh.points;
    std::mt19937 random(5);
    const double h = mean_edge_length(clean, s.mesh.triangles);
    std::normal_distribution<double> gauss(0.0, 0.3 * h);
    for (Eigen::Index v = 0; v < s.mesh.points.rows(); ++v)
        for (int k = 0; k < 3; ++k) s.mesh.points(v, k) += gauss(random);
    const FilterSpec& spec = *find_filter("denoise");
    const RunOutput out = run_filter(spec, default_values(spec, true), {s.mesh.points, s.mesh.triangles, s.one_bump, {}});
    std::string log;
    for (const auto& line : out.log) log += line + "\n";
    EXPECT_TRUE(logged(out, "took its lowpass's motion across the surface")) << log;
    const auto tangential_rms = [&](const Points& p) {
        double sum = 0;
        for (Eigen::Index v = 0; v < p.rows(); ++v) {
            const Eigen::RowVector3d n = clean.row(v).normalized(), e = p.row(v) - clean.row(v);
            sum += (e - e.dot(n) * n).squaredNorm();
        }
        return std::sqrt(sum / static_cast<double>(p.rows()));
    };
    EXPECT_LT(tangential_rms(out.points), 0.7 * tangential_rms(s.mesh.points)) << log;
    EXPECT_LT(rms_distance(out.points, clean), 0.7 * rms_distance(s.mesh.points, clean)) << log;
}

TEST(BumpPattern, ABumpInAHollowDeeperThanItselfIsStillABump) {
    // The surface's own detail at the bumps' scale: under the selected bump (or dent) a hollow
    // (or mound) 1.5 rho wide and 1.5 x the bump's height deep; the bump is still a peak. What
    // the lowpass removes is then negative on average over the selected bump, and lower there
    // than on the ring around it: either sign took the bump for a dent, and on a scan the
    // "dents" subtracted were the scan's own hollows (the diplodocus: RMS 4.4 x the input's,
    // volume +27 %). The truth is the sphere with the
    // hollow; whatever Denoise makes of it, it must not end farther from it than the input.
    for (int side : {1, -1}) {
        SCOPED_TRACE(side > 0 ? "bump in a hollow" : "dent on a mound");
        BumpySphere s = bumpy_sphere(side, 0.08, 150);
        Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
        for (int f : s.one_bump)
            for (int k = 0; k < 3; ++k) centre += s.mesh.points.row(s.mesh.triangles(f, k));
        centre.normalize();
        Points truth = icosphere(6, 1.0).points;
        for (Eigen::Index v = 0; v < truth.rows(); ++v) {
            const double d = (truth.row(v).normalized() - centre).norm();
            const double hollow = side * 1.5 * 0.24 * 0.08 * std::exp(-d * d / (1.5 * 0.08 * 1.5 * 0.08));
            truth.row(v) *= 1 - hollow;
            s.mesh.points.row(v) -= hollow * s.mesh.points.row(v).normalized();
        }
        const FilterSpec& spec = *find_filter("denoise");
        const RunOutput out =
            run_filter(spec, default_values(spec, true), {s.mesh.points, s.mesh.triangles, s.one_bump, {}});
        ASSERT_TRUE(out.feature);
        BumpPatternReport pattern;
        remove_bump_pattern(s.mesh.points, apply_filter(s.mesh.points, s.mesh.triangles, out.transfer),
                            s.mesh.triangles, s.one_bump, out.feature->radius, out.transfer, FilterOptions{}, &pattern);
        EXPECT_EQ(pattern.side, side);
        auto rms = [&](const Points& p) { return std::sqrt((p - truth).rowwise().squaredNorm().mean()); };
        const double truth_volume = volume(truth, s.mesh.triangles);
        auto volume_error = [&](const Points& p) { return std::abs(volume(p, s.mesh.triangles) - truth_volume); };
        EXPECT_LE(rms(out.points), rms(s.mesh.points));
        // No pattern explains the bump in its hollow here, and the flat lowpass that is returned
        // then keeps the bumps' mean height: the volume stays about as far from the truth as the
        // input's (measured 0.0589 against 0.0585, 0.05735 against 0.05730), not farther by more.
        EXPECT_LE(volume_error(out.points), 1.02 * volume_error(s.mesh.points));
    }
}

TEST(BumpPattern, ASelectionThatIsNoBumpLeavesTheMeshAsItWas) {
    // A cap of a bare sphere: what the lowpass removed is the same everywhere, nothing varies
    // for bumps to explain.
    const Mesh s = icosphere(5, 1.0);
    std::vector<int> cap;
    for (Eigen::Index f = 0; f < s.triangles.rows(); ++f)
        if (s.points(s.triangles(f, 0), 2) > 0.95 && s.points(s.triangles(f, 1), 2) > 0.95 &&
            s.points(s.triangles(f, 2), 2) > 0.95)
            cap.push_back(static_cast<int>(f));
    const FilterSpec& spec = *find_filter("denoise");
    const RunOutput out = run_filter(spec, default_values(spec, true), {s.points, s.triangles, cap, {}});
    EXPECT_EQ(out.points, s.points);
    EXPECT_TRUE(logged(out, "nothing at this size was removed"));
}

TEST(BumpPattern, RefusesAnEmptySelectionAndABadRadius) {
    const Mesh s = icosphere(2, 1.0);
    const TransferFunction g = design_butterworth_lowpass(10.0, 4);
    EXPECT_THROW(remove_bump_pattern(s.points, s.points, s.triangles, {}, 0.1, g, {}), Error);
    EXPECT_THROW(remove_bump_pattern(s.points, s.points, s.triangles, {0}, 0.0, g, {}), Error);
    EXPECT_THROW(remove_bump_pattern(s.points, s.points, s.triangles, {0}, NAN, g, {}), Error);
}

TEST(FilterField, ScalesASpheresCoordinateFunctionsByTheGainAtTwo) {
    // x, y, z on the unit sphere are eigenfunctions at s = 2: G(M^-1 K) x = G(2) x. Here as a
    // field on a sphere of radius 3, whose operator has them at 2/9.
    Mesh big = icosphere(5, 1.0);
    const Eigen::MatrixXd field = big.points;
    big.points *= 3.0;
    const TransferFunction g = design_butterworth_lowpass(1.0, 4);
    const Eigen::MatrixXd filtered = filter_field(big.points, big.triangles, g, field);
    const double expected = g(2.0 / 9.0);
    EXPECT_LT((filtered - expected * field).cwiseAbs().maxCoeff(), 2e-3 * expected);
    EXPECT_GT(std::abs(expected - 1.0), 0.001);  // the gain is not trivially 1
    // A field of the wrong height is refused.
    EXPECT_THROW(filter_field(big.points, big.triangles, g, field.topRows(10)), Error);
}

TEST(BumpPattern, OnAnOpenPatchTheBoundaryIsHeldAndTheResultEndsCloserToTheTruth) {
    // A gently waving open square with a pattern of Gaussian bumps and dents, one bump
    // selected. The free boundary of a lowpass at the bump's size pulls the rim inwards, and
    // with it the whole patch: farther from the bare patch than the bumpy input.
    Mesh truth = grid(120, 1.0);
    for (Eigen::Index i = 0; i < truth.points.rows(); ++i)
        truth.points(i, 2) = 0.04 * std::sin(5 * truth.points(i, 0) + 1) * std::cos(4 * truth.points(i, 1));
    const double rho = 0.04;
    std::mt19937 random(11);
    std::uniform_real_distribution<double> uniform(-0.45, 0.45);
    std::vector<Eigen::RowVector2d> centres;
    while (centres.size() < 24) {
        const Eigen::RowVector2d c(uniform(random), uniform(random));
        if (std::all_of(centres.begin(), centres.end(), [&](const auto& o) { return (o - c).norm() >= 1.6 * rho; }))
            centres.push_back(c);
    }
    Points bumpy = truth.points;
    for (Eigen::Index v = 0; v < bumpy.rows(); ++v)
        for (size_t k = 0; k < centres.size(); ++k) {
            const double d = (bumpy.row(v).head<2>() - centres[k]).norm();
            bumpy(v, 2) += (k % 3 == 2 ? -1 : 1) * 0.24 * rho * std::exp(-d * d / (rho * rho));
        }
    std::vector<int> selected;
    for (Eigen::Index f = 0; f < truth.triangles.rows(); ++f) {
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside = inside && (bumpy.row(truth.triangles(f, k)).head<2>() - centres[0]).norm() < rho;
        if (inside) selected.push_back(static_cast<int>(f));
    }
    const FilterSpec& spec = *find_filter("denoise");
    const RunOutput out = run_filter(spec, default_values(spec, true), {bumpy, truth.triangles, selected, {}});
    const double input = rms_distance(bumpy, truth.points), denoised = rms_distance(out.points, truth.points);
    const double free_lowpass = rms_distance(apply_filter(bumpy, truth.triangles, out.transfer), truth.points);
    EXPECT_GT(free_lowpass, input) << "the case must be one the free boundary fails";
    EXPECT_LT(denoised, 0.7 * input) << "free lowpass " << free_lowpass;
    EXPECT_TRUE(logged(out, "open boundary held in place"));
    // The outline stays: the rim moves only where a fitted bump reaches it, and then across
    // the surface (a free lowpass pulls it in by a good part of the bump's radius).
    const std::vector<bool> rim = boundary_vertices(truth.triangles, truth.points.rows());
    double rim_drift = 0;
    for (Eigen::Index v = 0; v < bumpy.rows(); ++v)
        if (rim[static_cast<size_t>(v)]) rim_drift = std::max(rim_drift, (out.points.row(v) - bumpy.row(v)).head<2>().norm());
    EXPECT_LT(rim_drift, 0.01 * rho);
}

TEST(BumpPattern, AFlatLowpassForAWideSelectionEndsCloserThanTheLowpassCutForTheSelection) {
    // Raised-cosine bumps and dents on a sphere with large smooth bumps of its own, one bump
    // selected generously (faces out to 1.6 of its radius, as a user's footprint). Where the
    // Gaussian profile leaves the selected bump mostly unexplained, the flat lowpass is the
    // fallback; cut for the selection it takes the base's large bumps too (on these patterns
    // it ended farther from the truth than the input). It is cut for the fitted width where
    // that is narrower, and what it removed of the base is put back. Five patterns; every one
    // that falls back must end closer to the truth than the input and than the plain lowpass
    // at the paper's cut for the selection, and both cuts must be taken at least once.
    const double rho = 0.065;
    int narrower = 0, for_selection_cut = 0;
    for (int seed = 1; seed <= 5; ++seed) {
        SCOPED_TRACE("pattern " + std::to_string(seed));
        Mesh truth = icosphere(6, 1.0);
        std::mt19937 random(seed);
        std::normal_distribution<double> gauss;
        const auto random_direction = [&] { return Eigen::RowVector3d(gauss(random), gauss(random), gauss(random)).normalized(); };
        std::vector<Eigen::RowVector3d> large;
        for (int k = 0; k < 6; ++k) large.push_back(random_direction());
        for (Eigen::Index v = 0; v < truth.points.rows(); ++v) {
            const Eigen::RowVector3d n = truth.points.row(v).normalized();
            double h = 0;
            for (const auto& c : large) h += 0.12 * std::exp(-(n - c).squaredNorm() / (0.4 * 0.4));
            truth.points.row(v) = n * (1 + h);
        }
        std::vector<Eigen::RowVector3d> centres;
        while (centres.size() < 70) {
            const Eigen::RowVector3d c = random_direction();
            if (std::all_of(centres.begin(), centres.end(), [&](const auto& o) { return (o - c).norm() >= 1.6 * rho; }))
                centres.push_back(c);
        }
        Points bumpy = truth.points;
        for (Eigen::Index v = 0; v < bumpy.rows(); ++v) {
            const Eigen::RowVector3d n = truth.points.row(v).normalized();
            double h = 0;
            for (size_t k = 0; k < centres.size(); ++k) {
                const double d = (n - centres[k]).norm();
                if (d < 2 * rho) h += (k % 2 ? -1 : 1) * 0.24 * rho * 0.5 * (1 + std::cos(M_PI * d / (2 * rho)));
            }
            bumpy.row(v) += h * n;
        }
        std::vector<int> selected;
        for (Eigen::Index f = 0; f < truth.triangles.rows(); ++f) {
            bool inside = true;
            for (int k = 0; k < 3; ++k)
                inside = inside && (bumpy.row(truth.triangles(f, k)).normalized() - centres[0]).norm() < 1.6 * rho;
            if (inside) selected.push_back(static_cast<int>(f));
        }
        const FilterSpec& spec = *find_filter("denoise");
        const ParameterValues values = default_values(spec, true);
        const RunOutput out = run_filter(spec, values, {bumpy, truth.triangles, selected, {}});
        const bool for_width = logged(out, "fell back to the flat lowpass (cut for the fitted width");
        const bool fell_back = logged(out, "fell back to the flat lowpass");
        if (!fell_back) continue;
        narrower += for_width;
        for_selection_cut += !for_width;
        FilterOptions options = filter_options(spec, values);
        options.op = out.op;
        const double for_selection =
            rms_distance(keep_normal_motion(bumpy, apply_filter(bumpy, truth.triangles, out.transfer, options), truth.triangles),
                         truth.points);
        const double input = rms_distance(bumpy, truth.points), denoised = rms_distance(out.points, truth.points);
        EXPECT_LT(denoised, input);
        EXPECT_LT(denoised, for_selection) << "input " << input;
    }
    EXPECT_GE(narrower, 1) << "no pattern took the cut for the fitted width: the test checks less than it says";
    EXPECT_GE(for_selection_cut, 1) << "no pattern took the cut for the selection: the test checks less than it says";
}

TEST(BumpPattern, BumpsAndDentsThatExplainTheSelectionButNotTheRestOfTheSurfaceAreNotSubtracted) {
    // Gaussian bumps and dents on the upper half of a sphere, one bump at the pole selected;
    // the lower half carries the surface's own texture instead: 1500 mounds and hollows as
    // high as the bumps and 0.3-0.6 of their width. Around the selection the pattern explains
    // what the lowpass removed; elements of both signs follow part of the texture too, but
    // across the surface the fit leaves more than half of it unexplained (with the texture's
    // heights shrunk with its widths, 0.3-0.6 as high, 49 %: the check is coarse). The flat
    // lowpass, the documented fallback, is returned instead, and the log says why.
    const double rho = 0.08;
    Mesh truth = icosphere(6, 1.0);
    std::mt19937 random(5);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<Eigen::RowVector3d> centres{Eigen::RowVector3d(0, 0, 1)};
    while (centres.size() < 40) {
        const Eigen::RowVector3d c = Eigen::RowVector3d(gauss(random), gauss(random), std::abs(gauss(random))).normalized();
        if (c[2] > 0.3 &&
            std::all_of(centres.begin(), centres.end(), [&](const auto& o) { return (o - c).norm() >= 1.6 * rho; }))
            centres.push_back(c);
    }
    struct Element {
        Eigen::RowVector3d centre;
        double width, height;
    };
    std::vector<Element> texture;
    while (texture.size() < 1500) {
        const Eigen::RowVector3d c = Eigen::RowVector3d(gauss(random), gauss(random), -std::abs(gauss(random))).normalized();
        const double width = rho * (0.3 + 0.3 * uniform(random));
        texture.push_back({c, width, 0.24 * rho * (uniform(random) < 0.5 ? -1 : 1) * (0.3 + 0.7 * uniform(random))});
    }
    for (Eigen::Index v = 0; v < truth.points.rows(); ++v) {
        const Eigen::RowVector3d n = truth.points.row(v);
        double h = 0;
        for (const auto& e : texture) h += e.height * std::exp(-(n - e.centre).squaredNorm() / (e.width * e.width));
        truth.points.row(v) = n * (1 + (n[2] < 0 ? 1.0 : std::exp(-n[2] * n[2] / 0.01)) * h);
    }
    Points bumpy = truth.points;
    for (Eigen::Index v = 0; v < bumpy.rows(); ++v) {
        const Eigen::RowVector3d n = truth.points.row(v).normalized();
        double h = 0;
        for (size_t k = 0; k < centres.size(); ++k)
            h += (k % 2 ? -1 : 1) * 0.24 * rho * std::exp(-(n - centres[k]).squaredNorm() / (rho * rho));
        bumpy.row(v) += h * n;
    }
    std::vector<int> selected;
    for (Eigen::Index f = 0; f < truth.triangles.rows(); ++f) {
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside = inside && (truth.points.row(truth.triangles(f, k)).normalized() - centres[0]).norm() < rho;
        if (inside) selected.push_back(static_cast<int>(f));
    }
    const FilterSpec& spec = *find_filter("denoise");
    const ParameterValues values = default_values(spec, true);
    const RunOutput out = run_filter(spec, values, {bumpy, truth.triangles, selected, {}});
    std::string log;
    for (const auto& line : out.log) log += line + "\n";
    ASSERT_TRUE(out.feature);
    BumpPatternReport pattern;
    remove_bump_pattern(bumpy, apply_filter(bumpy, truth.triangles, out.transfer), truth.triangles, selected,
                        out.feature->radius, out.transfer, FilterOptions{}, &pattern);
    EXPECT_LE(pattern.unexplained, bump_max_unexplained) << log;  // the selection alone is explained
    EXPECT_GT(pattern.opposite, 0) << log;
    EXPECT_GT(pattern.unexplained_everywhere, bump_max_unexplained) << log;
    EXPECT_FALSE(pattern.removed);
    EXPECT_TRUE(logged(out, "does not explain the rest of the surface")) << log;
    EXPECT_EQ(out.points, flat_lowpass_for_selection(bumpy, truth.triangles, selected)) << log;
}

namespace {

// 150 Gaussian bumps exp(-(d / rho_i)^2) 0.24 rho_i high on the unit sphere, their radii
// rho_i spread +-30 % about 0.07, and the faces of the first one selected.
struct MixedSizes {
    Mesh bare = icosphere(6, 1.0);
    Points bumpy;
    std::vector<int> selected;
};

MixedSizes bumps_of_mixed_sizes() {
    const double rho = 0.07;
    MixedSizes out;
    const Mesh& bare = out.bare;
    std::mt19937 random(23);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> size(0.7, 1.3);
    std::vector<std::pair<Eigen::RowVector3d, double>> bumps;
    while (bumps.size() < 150) {
        const Eigen::RowVector3d c = Eigen::RowVector3d(gauss(random), gauss(random), gauss(random)).normalized();
        const double r = rho * size(random);
        if (std::all_of(bumps.begin(), bumps.end(), [&](const auto& o) { return (o.first - c).norm() >= 1.6 * std::max(r, o.second); }))
            bumps.emplace_back(c, r);
    }
    out.bumpy = bare.points;
    for (Eigen::Index v = 0; v < out.bumpy.rows(); ++v) {
        const Eigen::RowVector3d n = bare.points.row(v);
        double h = 0;
        for (const auto& [c, r] : bumps) h += 0.24 * r * std::exp(-(n - c).squaredNorm() / (r * r));
        out.bumpy.row(v) = n * (1 + h);
    }
    for (Eigen::Index f = 0; f < bare.triangles.rows(); ++f) {
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside = inside && (bare.points.row(bare.triangles(f, k)) - bumps[0].first).norm() < bumps[0].second;
        if (inside) out.selected.push_back(static_cast<int>(f));
    }
    return out;
}

// Denoise run on the mixed sizes through run_filter, its log as one text for failure messages,
// and the filter options it ran with (on its operator) for the core's rule run beside it.
struct MixedSizesRun {
    RunOutput out;
    std::string log;
    FilterOptions options;
};

MixedSizesRun denoise_mixed_sizes(const MixedSizes& m) {
    const FilterSpec& spec = *find_filter("denoise");
    const ParameterValues values = default_values(spec, true);
    MixedSizesRun r{run_filter(spec, values, {m.bumpy, m.bare.triangles, m.selected, {}}), {}, filter_options(spec, values)};
    for (const auto& line : r.out.log) r.log += line + "\n";
    r.options.op = r.out.op;
    return r;
}

} // namespace

TEST(BumpPattern, ElementsOfMixedSizesAreRemovedToo) {
    // One width leaves a ring or a cap of every bump it misses; each element is free to take
    // the profile at a few sizes. Checked against the bare sphere (at one width only: RMS 0.25
    // of the input's, volume 0.18 % off; measured now 0.12 and 0.06 %).
    const MixedSizes m = bumps_of_mixed_sizes();
    const auto [out, log, options] = denoise_mixed_sizes(m);
    EXPECT_TRUE(logged(out, "pattern of bumps removed")) << log;
    EXPECT_LT(rms_distance(out.points, m.bare.points), 0.18 * rms_distance(m.bumpy, m.bare.points)) << log;
    EXPECT_LT(std::abs(volume(out.points, m.bare.triangles) - bare_volume) / bare_volume, 0.001) << log;
}

TEST(BumpPattern, WhatThePatternLeavesIsLowpassedAway) {
    // The same bumps: the pattern subtracted alone (the core's rule with no lowpass to make)
    // leaves a ring or a cap where an element's fit was off; Denoise lowpasses that misfit at
    // 1.5 times the pattern's radius. Against the bare sphere the faces turn less and the
    // vertices end no farther, and the volume stays as the pattern left it (it has no mean
    // height left for the lowpass to keep or take).
    const MixedSizes m = bumps_of_mixed_sizes();
    const auto [out, log, options] = denoise_mixed_sizes(m);
    ASSERT_TRUE(logged(out, "pattern of bumps removed")) << log;
    ASSERT_TRUE(logged(out, "then what the pattern did not explain was lowpassed away")) << log;
    const Points lowpassed = apply_filter(m.bumpy, m.bare.triangles, out.transfer, options);
    const SelectedBumpDenoise alone = denoise_selected_bump(m.bumpy, lowpassed, m.bare.triangles, m.selected, out.feature->radius,
                                                            out.transfer, options, nullptr);
    ASSERT_EQ(alone.outcome, SelectedBumpOutcome::PatternRemoved);
    ASSERT_FALSE(alone.misfit_lowpassed);
    const auto turn = [&](const Points& p) { return reference::mean_normal_error_degrees(p, m.bare.points, m.bare.triangles); };
    EXPECT_LT(turn(out.points), 0.7 * turn(alone.points)) << log;
    EXPECT_LE(rms_distance(out.points, m.bare.points), rms_distance(alone.points, m.bare.points)) << log;
    EXPECT_LT(std::abs(volume(out.points, m.bare.triangles) - bare_volume) / bare_volume, 0.001) << log;
}

TEST(BumpPattern, AMisfitLowpassThatWouldChangeTheVolumeIsNotApplied) {
    // The guard on the misfit's lowpass, fed a lowpass that shrinks what it is given by 1 %
    // (a closed part's volume by 3 %, as a lowpass at the bumps' size shrinks a leg as thin as
    // them): the pattern is still removed, the shrinking is not, and its volume change is
    // reported. The input itself (a refit under a narrower cut) gets the true lowpass.
    const MixedSizes m = bumps_of_mixed_sizes();
    const MixedSizesRun mixed = denoise_mixed_sizes(m);
    const RunOutput& run = mixed.out;
    const FilterOptions& options = mixed.options;
    ASSERT_TRUE(run.feature.has_value()) << mixed.log;
    const LowpassForBump shrinking = [&](const Points& at, double radius) {
        FeatureEllipsoid bump = *run.feature;
        bump.radius = radius;
        const DenoiseDesign d = design_denoise_from_bump(bump, FeatureShape::Sphere, 4, run.op);
        if (at.rows() == m.bumpy.rows() && at == m.bumpy) return LowpassedForBump{apply_filter(at, m.bare.triangles, d.g, options), d.g};
        return LowpassedForBump{Points(0.99 * at), d.g};
    };
    const Points lowpassed = apply_filter(m.bumpy, m.bare.triangles, run.transfer, options);
    const SelectedBumpDenoise out = denoise_selected_bump(m.bumpy, lowpassed, m.bare.triangles, m.selected, run.feature->radius,
                                                          run.transfer, options, shrinking);
    ASSERT_EQ(out.outcome, SelectedBumpOutcome::PatternRemoved);
    EXPECT_FALSE(out.misfit_lowpassed);
    EXPECT_NEAR(out.misfit_volume_change, 1 - std::pow(0.99, 3), 2e-3);
    EXPECT_LT(std::abs(volume(out.points, m.bare.triangles) - bare_volume) / bare_volume, 0.001);
    EXPECT_LT(rms_distance(out.points, m.bare.points), 0.18 * rms_distance(m.bumpy, m.bare.points));
}

TEST(BumpPattern, SharpRimmedDentsGetAProfileLearnedFromTheSelection) {
    // Spherical-cap dents sqrt(1 - (d / 1.5 rho_i)^2) 0.24 rho_i deep on a torus, radii spread
    // +-30 % about 0.045, covering a fifth of it; four patterns. A Gaussian profile leaves
    // each cap's rim; where the fit learns the profile from the selected dent and its
    // neighbours and the pattern is removed, the result must end within 0.3 of the input's RMS
    // distance to the bare torus and keep its volume to 0.05 % (with the Gaussian: 0.31-0.32
    // and 0.15 %; learned, measured 0.24-0.28 and 0.01-0.02 %). Whatever path a pattern takes,
    // it must end closer to the bare torus than its input.
    int learned = 0;
    for (unsigned seed : {1u, 2u, 3u, 4u}) {
        SCOPED_TRACE("pattern " + std::to_string(seed));
        const Mesh bare = torus(240, 96, 1.0, 0.4);
        std::mt19937 random(seed);
        std::uniform_int_distribution<Eigen::Index> pick(0, bare.points.rows() - 1);
        std::uniform_real_distribution<double> size(0.7, 1.3);
        const double rho = 0.045;
        const auto normal = [](const Eigen::RowVector3d& p) {
            const Eigen::RowVector3d core = Eigen::RowVector3d(p[0], p[1], 0).normalized();
            return Eigen::RowVector3d((p - core).normalized());
        };
        std::vector<std::pair<Eigen::Index, double>> dents;
        double covered = 0;
        const double area = 4 * M_PI * M_PI * 1.0 * 0.4;
        for (int tries = 0; tries < 100000 && covered < 0.2 * area; ++tries) {
            const Eigen::Index i = pick(random);
            const double r = rho * size(random);
            if (std::all_of(dents.begin(), dents.end(), [&](const auto& o) {
                    return (bare.points.row(o.first) - bare.points.row(i)).norm() >= 1.2 * std::max(r, o.second);
                })) {
                dents.emplace_back(i, r);
                covered += M_PI * 2.25 * r * r;
            }
        }
        Points dented = bare.points;
        for (Eigen::Index v = 0; v < dented.rows(); ++v) {
            double depth = 0;
            for (const auto& [i, r] : dents) {
                const double d = (bare.points.row(v) - bare.points.row(i)).norm();
                if (d < 1.5 * r) depth += 0.24 * r * std::sqrt(1 - d * d / (2.25 * r * r));
            }
            dented.row(v) -= depth * normal(bare.points.row(v));
        }
        std::vector<int> selected;
        for (Eigen::Index f = 0; f < bare.triangles.rows(); ++f) {
            bool inside = true;
            for (int k = 0; k < 3; ++k)
                inside = inside && (bare.points.row(bare.triangles(f, k)) - bare.points.row(dents[0].first)).norm() < 1.2 * dents[0].second;
            if (inside) selected.push_back(static_cast<int>(f));
        }
        const FilterSpec& spec = *find_filter("denoise");
        const RunOutput out = run_filter(spec, default_values(spec, true), {dented, bare.triangles, selected, {}});
        std::string log;
        for (const auto& line : out.log) log += line + "\n";
        const double input = rms_distance(dented, bare.points), denoised = rms_distance(out.points, bare.points);
        EXPECT_LT(denoised, input) << log;
        if (!logged(out, "pattern of bumps removed") || !logged(out, "profile learned")) continue;
        ++learned;
        const double bare_torus = volume(bare.points, bare.triangles);
        EXPECT_LT(denoised, 0.3 * input) << log;
        EXPECT_LT(std::abs(volume(out.points, bare.triangles) - bare_torus) / bare_torus, 5e-4) << log;
    }
    EXPECT_GE(learned, 1) << "no pattern was removed with a learned profile: the test checks nothing";
}
