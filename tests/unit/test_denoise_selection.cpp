// Denoise with a selection or a region never flattens what it was asked to clean and never
// silently returns the input: on a region it removes sampling noise (the rule chosen on the
// mesh) and leaves everything outside the region bit for bit; a selection too large to be one
// bump gets the same rule; a selected bump no pattern explains gets the flat lowpass. Every
// check is against the noise-free surface the test built, never against the filter's numbers.
#include "core/denoise/bump_pattern.h"
#include "core/denoise/denoise.h"
#include "core/filter/region.h"
#include "core/mesh/surface_measures.h"
#include "run_filter.h"
#include "shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace geofilter;

namespace {

// Distance to the unit sphere, the noise-free surface, RMS over `vertices` (all when empty).
double rms_off_unit_sphere(const Points& p, const std::vector<int>& vertices = {}) {
    double sum = 0;
    const size_t count = vertices.empty() ? static_cast<size_t>(p.rows()) : vertices.size();
    for (size_t i = 0; i < count; ++i) {
        const Eigen::Index v = vertices.empty() ? static_cast<Eigen::Index>(i) : vertices[i];
        sum += std::pow(p.row(v).norm() - 1.0, 2);
    }
    return std::sqrt(sum / static_cast<double>(count));
}

std::vector<int> faces_where(const Points& p, const Triangles& t, double min_z) {
    std::vector<int> faces;
    for (Eigen::Index f = 0; f < t.rows(); ++f)
        if (p(t(f, 0), 2) > min_z && p(t(f, 1), 2) > min_z && p(t(f, 2), 2) > min_z) faces.push_back(static_cast<int>(f));
    return faces;
}

std::vector<int> corners_of(const Triangles& t, const std::vector<int>& faces) {
    std::vector<bool> in(static_cast<size_t>(t.maxCoeff() + 1), false);
    for (int f : faces)
        for (int k = 0; k < 3; ++k) in[static_cast<size_t>(t(f, k))] = true;
    std::vector<int> out;
    for (size_t v = 0; v < in.size(); ++v)
        if (in[v]) out.push_back(static_cast<int>(v));
    return out;
}

bool logged(const RunOutput& out, const std::string& text) {
    for (const auto& line : out.log)
        if (line.find(text) != std::string::npos) return true;
    return false;
}

std::string joined(const RunOutput& out) {
    std::string s;
    for (const auto& line : out.log) s += line + "\n";
    return s;
}

struct NoisySphere {
    Mesh clean = icosphere(4, 1.0);  // 2562 vertices
    Points noisy;
    NoisySphere() {
        const double h = mean_edge_length(clean.points, clean.triangles);
        noisy = noised_along_normals(clean, 0.3 * h, 11);
    }
};

} // namespace

TEST(DenoiseSelection, OnARegionDenoisesInsideAndLeavesEverythingOutsideBitForBit) {
    const NoisySphere s;
    const std::vector<int> region = faces_where(s.noisy, s.clean.triangles, 0.5);
    ASSERT_GT(region.size(), 50u);
    const std::vector<int> inside = corners_of(s.clean.triangles, region);
    const FilterSpec& spec = *find_filter("denoise");
    for (double blend : {0.0, 0.15}) {
        SCOPED_TRACE("blendWidth " + std::to_string(blend));
        ParameterValues values = default_values(spec, true);
        values[param::region] = 1;
        values[param::blend_width] = blend;
        const RunOutput out = run_filter(spec, values, {s.noisy, s.clean.triangles, region, {}});
        const double before = rms_off_unit_sphere(s.noisy, inside), after = rms_off_unit_sphere(out.points, inside);
        EXPECT_LT(after, 0.7 * before) << joined(out);
        // Not the flattening a lowpass cut at the region's size makes: that pulls the cap in by
        // far more than the noise.
        EXPECT_LT(after, before);
        // Outside the band the weight is 0: those vertices are the input's, bit for bit. With
        // auto, the band Denoise documents.
        const double band = blend > 0 ? blend : denoise_blend_edges * mean_edge_length(s.noisy, s.clean.triangles);
        const std::vector<double> weight = region_weight(s.noisy, s.clean.triangles, region, band);
        int outside = 0, moved_inside = 0;
        for (Eigen::Index v = 0; v < s.noisy.rows(); ++v) {
            if (weight[v] == 0) {
                ++outside;
                EXPECT_EQ(out.points.row(v), s.noisy.row(v)) << "vertex " << v;
            }
        }
        for (int v : inside) moved_inside += out.points.row(v) != s.noisy.row(v);
        EXPECT_GT(outside, s.noisy.rows() / 3);
        EXPECT_EQ(moved_inside, static_cast<int>(inside.size()));
        EXPECT_TRUE(logged(out, "sampling-noise rule")) << joined(out);
        EXPECT_TRUE(logged(out, "the selection is the region to denoise")) << joined(out);
        EXPECT_FALSE(out.feature);
        if (blend == 0) EXPECT_TRUE(logged(out, "auto: ")) << joined(out);
    }
}

TEST(DenoiseSelection, QualityAsWeightDenoisesWhereTheWeightIsAndNowhereElse) {
    const NoisySphere s;
    std::vector<double> quality(static_cast<size_t>(s.noisy.rows()));
    std::vector<int> weighted;
    for (Eigen::Index v = 0; v < s.noisy.rows(); ++v) {
        quality[v] = s.noisy(v, 2) > 0 ? 1.0 : 0.0;
        if (quality[v] > 0) weighted.push_back(static_cast<int>(v));
    }
    const FilterSpec& spec = *find_filter("denoise");
    ParameterValues values = default_values(spec, false);
    values[param::region] = 2;
    // Left on with nothing selected (MeshLab keeps the last value): on a region there is no
    // bump to measure, so it does not matter.
    values[param::use_selection] = 1;
    RunInput input{s.noisy, s.clean.triangles, {}, {}};
    input.vertex_quality = &quality;
    const RunOutput out = run_filter(spec, values, input);
    EXPECT_LT(rms_off_unit_sphere(out.points, weighted), 0.7 * rms_off_unit_sphere(s.noisy, weighted));
    for (Eigen::Index v = 0; v < s.noisy.rows(); ++v)
        if (quality[v] == 0) EXPECT_EQ(out.points.row(v), s.noisy.row(v)) << "vertex " << v;
}

TEST(DenoiseSelection, ASelectionOfMostOfTheMeshIsNoBumpAndGetsTheSamplingNoiseRule) {
    const NoisySphere s;
    // A leftover selection: everything above z = -0.4, 70 % of the sphere's area.
    const std::vector<int> most = faces_where(s.noisy, s.clean.triangles, -0.4);
    ASSERT_GT(selected_area_share(s.noisy, s.clean.triangles, most), 0.5);
    const FilterSpec& spec = *find_filter("denoise");
    const RunOutput out = run_filter(spec, default_values(spec, true), {s.noisy, s.clean.triangles, most, {}});
    EXPECT_TRUE(logged(out, "no bump of a pattern")) << joined(out);
    EXPECT_TRUE(logged(out, "sampling-noise rule")) << joined(out);
    EXPECT_FALSE(logged(out, "nothing was removed"));
    EXPECT_LT(rms_off_unit_sphere(out.points), 0.7 * rms_off_unit_sphere(s.noisy));
    // The same as with nothing selected: the selection played no part.
    const RunOutput unselected = run_filter(spec, default_values(spec, false), {s.noisy, s.clean.triangles, {}, {}});
    EXPECT_EQ(out.points, unselected.points);
}

TEST(DenoiseSelection, ABumpOfAPatternOfBumpsAndDentsIsNotLeftAsItWas) {
    // Bumps and dents alternating on the unit sphere, the dents 1.5 times as deep: bumps alone
    // leave half of what the lowpass removed unexplained; the dents, fitted on what the bumps
    // leave, explain most of the rest, and both are removed.
    Mesh m = icosphere(5, 1.0);
    const double rho = 0.08;
    std::mt19937 random(5);
    std::normal_distribution<double> gauss;
    std::vector<Eigen::RowVector3d> centres;
    while (centres.size() < 80) {
        const Eigen::RowVector3d c = Eigen::RowVector3d(gauss(random), gauss(random), gauss(random)).normalized();
        if (std::all_of(centres.begin(), centres.end(), [&](const auto& o) { return (o - c).norm() >= 1.6 * rho; }))
            centres.push_back(c);
    }
    for (Eigen::Index v = 0; v < m.points.rows(); ++v) {
        const Eigen::RowVector3d n = m.points.row(v).normalized();
        double h = 0;
        for (size_t i = 0; i < centres.size(); ++i) {
            const double d = (n - centres[i]).norm();
            h += (i % 2 == 0 ? 1.0 : -1.5) * 0.24 * rho * std::exp(-d * d / (rho * rho));
        }
        m.points.row(v) = n * (1 + h);
    }
    std::vector<int> bump;  // the first centre's, a bump
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
        bool in = true;
        for (int k = 0; k < 3; ++k) in = in && (m.points.row(m.triangles(f, k)).normalized() - centres[0]).norm() < rho;
        if (in) bump.push_back(static_cast<int>(f));
    }
    ASSERT_GT(bump.size(), 10u);
    const FilterSpec& spec = *find_filter("denoise");
    const RunOutput out = run_filter(spec, default_values(spec, true), {m.points, m.triangles, bump, {}});
    EXPECT_NE(out.points, m.points) << joined(out);
    EXPECT_LT(rms_off_unit_sphere(out.points), 0.7 * rms_off_unit_sphere(m.points)) << joined(out);
    EXPECT_FALSE(logged(out, "left as it was")) << joined(out);
    // Both signs are one pattern: the dents are fitted on what the bumps' fit leaves.
    EXPECT_TRUE(logged(out, "of the other sign")) << joined(out);
}

TEST(RunFilter, RefusesCoordinatesThatAreNotFinite) {
    Points p = icosphere(1, 1.0).points;
    EXPECT_NO_THROW(require_finite_output(p));
    p(7, 1) = std::numeric_limits<double>::infinity();
    try {
        require_finite_output(p);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("the filtered coordinates are not finite (vertex 7"), std::string::npos)
            << e.what();
    }
    p(7, 1) = 0;
    p(3, 0) = std::nan("");
    EXPECT_THROW(require_finite_output(p), Error);
}
