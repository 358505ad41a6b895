// The region filter against an independent dense reference of its documented math:
// weight w from the edge-path distance to the selected faces (Bellman-Ford here, Dijkstra in
// the core), the Dirichlet problem on D = {w > 0} solved by a dense generalized eigen
// decomposition, and p_final = p + w (p' - p).
#include "core/mesh/boundary.h"
#include "core/filter/filter.h"
#include "core/filter/region.h"
#include "refusal.h"
#include "spectral.h"

#include <gtest/gtest.h>


#include <cmath>
#include <cstdio>
#include <limits>
#include <functional>
#include <map>

using namespace geofilter;
using namespace geofilter::reference;

namespace {

// A sphere with three smooth bumps of radius ~0.25: features at one scale, and a quiet
// surface between them.
Mesh bumpy_sphere() {
    Mesh m = icosphere(3, 1.0);
    const Eigen::Vector3d centres[3] = {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}};
    for (Eigen::Index i = 0; i < m.points.rows(); ++i) {
        const Eigen::Vector3d p = m.points.row(i).transpose();
        double r = 1;
        for (const auto& c : centres) r += 0.12 * std::exp(-(p - c).squaredNorm() / (2 * 0.2 * 0.2));
        m.points.row(i) = (r * p).transpose();
    }
    return m;
}

Mesh wavy_sheet() {
    Mesh g = grid(20, 1.0);
    for (Eigen::Index i = 0; i < g.points.rows(); ++i) {
        const double x = g.points(i, 0), y = g.points(i, 1);
        g.points(i, 2) = 0.05 * std::sin(9 * x) * std::cos(7 * y) + 0.1 * x * y;
    }
    return g;
}

std::vector<int> faces_within(const Mesh& m, const Eigen::Vector3d& centre, double radius) {
    std::vector<int> faces;
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside = inside && (m.points.row(m.triangles(f, k)).transpose() - centre).norm() < radius;
        if (inside) faces.push_back(static_cast<int>(f));
    }
    return faces;
}

// Reference weight: Bellman-Ford relaxation of every edge until nothing changes, then the
// documented profile 1 - 3t^2 + 2t^3.
std::vector<double> reference_weight(const Mesh& m, const std::vector<int>& faces, double width) {
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> d(static_cast<size_t>(m.points.rows()), inf);
    for (int f : faces)
        for (int k = 0; k < 3; ++k) d[m.triangles(f, k)] = 0;
    for (bool changed = true; changed;) {
        changed = false;
        for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
            for (int k = 0; k < 3; ++k) {
                const int a = m.triangles(f, k), b = m.triangles(f, (k + 1) % 3);
                const double len = (m.points.row(a) - m.points.row(b)).norm();
                if (d[a] + len < d[b]) { d[b] = d[a] + len; changed = true; }
                if (d[b] + len < d[a]) { d[a] = d[b] + len; changed = true; }
            }
    }
    std::vector<double> w(d.size(), 0.0);
    for (size_t i = 0; i < d.size(); ++i) {
        if (d[i] == 0) w[i] = 1;
        else if (d[i] < width) {
            const double t = d[i] / width;
            w[i] = 1 - 3 * t * t + 2 * t * t * t;
        }
    }
    return w;
}

// Dense reference of the Dirichlet problem on D = {w > 0} with everything else (and, if
// asked, the open boundary) fixed: p' = h + V G(Lambda) V^T M (p - h) on the free vertices,
// then p + w (p' - p). Needs at least one fixed vertex coupled to D.
Points reference_region_filter(const Mesh& m, const std::vector<double>& w, const TransferFunction& g, bool fix_boundary) {
    const Laplacian l = cotan_laplacian(m.points, m.triangles);
    const Eigen::MatrixXd k = Eigen::MatrixXd(l.stiffness);
    const std::vector<bool> rim = boundary_vertices(m.triangles, m.points.rows());
    std::vector<int> free_rows, fixed_rows;
    for (Eigen::Index i = 0; i < m.points.rows(); ++i)
        (w[i] > 0 && !(fix_boundary && rim[i]) ? free_rows : fixed_rows).push_back(static_cast<int>(i));
    const auto nf = static_cast<Eigen::Index>(free_rows.size()), nb = static_cast<Eigen::Index>(fixed_rows.size());
    Eigen::MatrixXd kff(nf, nf), kfb(nf, nb), pf(nf, 3), pb(nb, 3);
    Eigen::VectorXd mf(nf);
    for (Eigen::Index a = 0; a < nf; ++a) {
        for (Eigen::Index b = 0; b < nf; ++b) kff(a, b) = k(free_rows[a], free_rows[b]);
        for (Eigen::Index b = 0; b < nb; ++b) kfb(a, b) = k(free_rows[a], fixed_rows[b]);
        pf.row(a) = m.points.row(free_rows[a]);
        mf[a] = l.mass[free_rows[a]];
    }
    for (Eigen::Index b = 0; b < nb; ++b) pb.row(b) = m.points.row(fixed_rows[b]);
    const Eigen::MatrixXd h = kff.ldlt().solve(-kfb * pb);
    const reference::Spectrum eig = reference::dense_spectrum(kff, mf);
    Eigen::VectorXd gains(nf);
    for (Eigen::Index i = 0; i < nf; ++i) gains[i] = g(std::max(0.0, eig.eigenvalues[i]));
    const Eigen::MatrixXd filtered =
        h + eig.eigenvectors * (gains.asDiagonal() * (eig.eigenvectors.transpose() * (mf.asDiagonal() * (pf - h))));
    Points out = m.points;
    for (Eigen::Index a = 0; a < nf; ++a) {
        const int v = free_rows[a];
        out.row(v) = m.points.row(v) + w[v] * (filtered.row(a) - m.points.row(v));
    }
    return out;
}

// Dihedral angle (between the two face normals) of every edge shared by exactly two faces.
std::map<std::pair<int, int>, double> dihedral_angles(const Points& p, const Triangles& t) {
    std::map<std::pair<int, int>, std::vector<Eigen::Vector3d>> normals;
    for (Eigen::Index f = 0; f < t.rows(); ++f) {
        const Eigen::Vector3d a = p.row(t(f, 0)), b = p.row(t(f, 1)), c = p.row(t(f, 2));
        const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
        for (int k = 0; k < 3; ++k) normals[std::minmax(t(f, k), t(f, (k + 1) % 3))].push_back(n);
    }
    std::map<std::pair<int, int>, double> angle;
    for (const auto& [edge, n] : normals)
        if (n.size() == 2) angle[edge] = std::atan2(n[0].cross(n[1]).norm(), n[0].dot(n[1]));
    return angle;
}

// The crease measure: the largest change |theta' - theta| of an edge's dihedral angle (the
// angle between its two face normals) over three sets of edges: the region's interior (both
// ends w = 1), the band (an end with 0 < w < 1, the other in D) and the outer border (one end
// in D, the other held fixed outside it, w = 0), where the filtered part meets the untouched.
struct CreaseMeasure {
    double interior = 0, band = 0, border = 0;
};

CreaseMeasure crease_measure(const Mesh& m, const Points& after, const std::vector<double>& w) {
    const auto before = dihedral_angles(m.points, m.triangles), now = dihedral_angles(after, m.triangles);
    CreaseMeasure c;
    for (const auto& [edge, theta] : before) {
        const double change = std::abs(now.at(edge) - theta);
        const double wa = w[edge.first], wb = w[edge.second];
        if (wa == 1 && wb == 1) c.interior = std::max(c.interior, change);
        else if (wa > 0 && wb > 0) c.band = std::max(c.band, change);
        else if (wa > 0 || wb > 0) c.border = std::max(c.border, change);
    }
    return c;
}

const TransferFunction& exaggerate() {
    static const TransferFunction g = design_second_order({2 / (0.2 * 0.2), 120, 1, 3, 0.9});
    return g;
}

void expect_outside_unchanged(const Points& out, const Points& in, const std::vector<double>& w) {
    for (Eigen::Index i = 0; i < in.rows(); ++i)
        if (w[i] == 0) {
            ASSERT_EQ(out(i, 0), in(i, 0)) << "vertex " << i;
            ASSERT_EQ(out(i, 1), in(i, 1)) << "vertex " << i;
            ASSERT_EQ(out(i, 2), in(i, 2)) << "vertex " << i;
        }
}

} // namespace

TEST(Region, BlendProfileIsC1AndFallsFromOneToZero) {
    EXPECT_EQ(blend_profile(0, 0.5), 1);
    EXPECT_EQ(blend_profile(0.5, 0.5), 0);
    EXPECT_EQ(blend_profile(0.7, 0.5), 0);
    EXPECT_EQ(blend_profile(0.1, 0), 0);  // no band: hard cut
    EXPECT_NEAR(blend_profile(0.25, 0.5), 0.5, 1e-15);
    const double e = 1e-6;
    EXPECT_NEAR((blend_profile(0.5, 0.5) - blend_profile(0.5 - e, 0.5)) / e, 0, 1e-4);  // zero slope at the band's edge
    EXPECT_NEAR((blend_profile(e, 0.5) - blend_profile(0, 0.5)) / e, 0, 1e-4);         // and at the region's
    for (double d = 0; d < 0.5; d += 0.01) EXPECT_GE(blend_profile(d, 0.5), blend_profile(d + 0.01, 0.5));
}

TEST(Region, WeightMatchesBellmanFordDistances) {
    const Mesh m = bumpy_sphere();
    const std::vector<int> faces = faces_within(m, {0, 0, 1.1}, 0.3);
    ASSERT_GT(faces.size(), 10u);
    for (double width : {0.0, 0.2, 0.45}) {
        const std::vector<double> w = region_weight(m.points, m.triangles, faces, width);
        const std::vector<double> ref = reference_weight(m, faces, width);
        for (size_t i = 0; i < w.size(); ++i) ASSERT_NEAR(w[i], ref[i], 1e-12) << "vertex " << i << ", width " << width;
    }
}

TEST(Region, SelectedRegionEqualsDenseDirichletReferenceAndLeavesTheRestBitForBit) {
    const Mesh m = bumpy_sphere();
    const std::vector<int> faces = faces_within(m, {0, 0, 1.1}, 0.3);
    const std::vector<double> w = region_weight(m.points, m.triangles, faces, 0.35);
    const Points ref = reference_region_filter(m, w, exaggerate(), false);
    const double diag = bbox_diagonal(m.points);
    for (Solver solver : {Solver::Factored, Solver::JacobiPcg}) {
        FilterOptions options;
        options.solver = solver;
        FilterReport report;
        RegionReport region;
        const Points out = apply_filter_weighted(m.points, m.triangles, exaggerate(), w, options, &report, &region);
        EXPECT_LT((out - ref).rowwise().norm().maxCoeff(), 1e-6 * diag) << solver_name(solver);
        expect_outside_unchanged(out, m.points, w);
        EXPECT_GT((out - m.points).rowwise().norm().maxCoeff(), 0.02) << "the bump must grow";
        EXPECT_GT(region.ring_vertices, 0);
        EXPECT_LT(region.submesh_vertices, m.points.rows() / 2) << "only the region and its ring are solved on";
        EXPECT_EQ(region.free_components, 0);
    }
}

TEST(Region, OpenBoundaryInsideTheRegionIsFreeOrFixedAsFixBoundarySays) {
    const Mesh m = wavy_sheet();
    const std::vector<int> faces = faces_within(m, {0.5, 0.5, 0}, 0.45);  // a corner of the sheet
    const std::vector<double> w = region_weight(m.points, m.triangles, faces, 0.2);
    const std::vector<bool> rim = boundary_vertices(m.triangles, m.points.rows());
    const double diag = bbox_diagonal(m.points);
    for (bool fix : {false, true}) {
        FilterOptions options;
        options.fix_boundary = fix;
        const Points out = apply_filter_weighted(m.points, m.triangles, exaggerate(), w, options);
        const Points ref = reference_region_filter(m, w, exaggerate(), fix);
        EXPECT_LT((out - ref).rowwise().norm().maxCoeff(), 1e-6 * diag) << "fixBoundary " << fix;
        expect_outside_unchanged(out, m.points, w);
        double rim_motion = 0;
        for (Eigen::Index i = 0; i < m.points.rows(); ++i)
            if (rim[i] && w[i] > 0) rim_motion = std::max(rim_motion, (out.row(i) - m.points.row(i)).norm());
        if (fix) EXPECT_EQ(rim_motion, 0);
        else EXPECT_GT(rim_motion, 1e-4) << "a free boundary moves with the surface";
    }
}

TEST(Region, WeightOneEverywhereIsTheWholeMeshFilterAndZeroChangesNothing) {
    Mesh m = torus(30, 20, 1.0, 0.35);
    perturb_radially(m, 0.02, 5);
    for (Solver solver : {Solver::Factored, Solver::JacobiPcg}) {
        FilterOptions options;
        options.solver = solver;
        const Points whole = apply_filter(m.points, m.triangles, exaggerate(), options);
        const Points one = apply_filter_weighted(m.points, m.triangles, exaggerate(),
                                                 std::vector<double>(size_t(m.points.rows()), 1.0), options);
        EXPECT_TRUE(one == whole) << "weight 1 must be the whole-mesh filter, bit for bit";
        FilterReport report;
        const Points zero = apply_filter_weighted(m.points, m.triangles, exaggerate(),
                                                  std::vector<double>(size_t(m.points.rows()), 0.0), options, &report);
        EXPECT_TRUE(zero == m.points);
        ASSERT_EQ(report.warnings.size(), 1u);
        EXPECT_NE(report.warnings[0].find("nothing changed"), std::string::npos);
    }
}

TEST(Region, AWholeComponentIsFilteredAloneAndTheOtherComponentUntouched) {
    Mesh a = icosphere(3, 0.5), b = icosphere(2, 0.3);
    perturb_radially(a, 0.01, 3);
    b.points.col(0).array() += 2.0;
    Mesh both;
    both.points.resize(a.points.rows() + b.points.rows(), 3);
    both.points << a.points, b.points;
    both.triangles.resize(a.triangles.rows() + b.triangles.rows(), 3);
    both.triangles << a.triangles, (b.triangles.array() + int(a.points.rows())).matrix();
    std::vector<int> faces(size_t(a.triangles.rows()));
    for (size_t f = 0; f < faces.size(); ++f) faces[f] = int(f);
    const std::vector<double> w = region_weight(both.points, both.triangles, faces, 0.3);
    const TransferFunction g = design_second_order({25, 100, 0, 2, 0});  // bandpass, G0 = 0: the centroid matters
    RegionReport region;
    const Points out = apply_filter_weighted(both.points, both.triangles, g, w, {}, nullptr, &region);
    const Points alone = apply_filter(a.points, a.triangles, g);
    EXPECT_EQ(region.ring_vertices, 0);
    EXPECT_TRUE(out.topRows(a.points.rows()) == alone);
    EXPECT_TRUE(out.bottomRows(b.points.rows()) == b.points);
}

TEST(Region, TheBlendDoesNotCreaseTheBorder) {
    const Mesh m = bumpy_sphere();
    const std::vector<int> faces = faces_within(m, {0, 0, 1.1}, 0.3);
    const std::vector<double> w = region_weight(m.points, m.triangles, faces, 0.35);
    const CreaseMeasure blended = crease_measure(m, apply_filter_weighted(m.points, m.triangles, exaggerate(), w), w);
    const std::vector<double> cut = region_weight(m.points, m.triangles, faces, 0);
    const CreaseMeasure hard = crease_measure(m, apply_filter_weighted(m.points, m.triangles, exaggerate(), cut), cut);
    const std::vector<double> all(size_t(m.points.rows()), 1.0);
    const CreaseMeasure whole = crease_measure(m, apply_filter(m.points, m.triangles, exaggerate()), all);
    std::printf("crease measure (max |change of dihedral angle|, radians): blend width 0.35: interior %.4g, band %.4g,"
                " border %.4g; hard cut: interior %.4g, border %.4g; whole-mesh filter %.4g\n",
                blended.interior, blended.band, blended.border, hard.interior, hard.border, whole.interior);
    EXPECT_GT(blended.interior, 0.01) << "the filter must act inside the region";
    // Within what the same filter does in the interior (of the region, and of the whole mesh).
    EXPECT_LE(blended.band, whole.interior);
    EXPECT_LE(blended.border, std::min(blended.interior, whole.interior));
    // The measure sees a crease: the hard cut (no band) bends its border more than the filter
    // bends anything inside, and the blend removes nearly all of that.
    EXPECT_GT(hard.border, whole.interior);
    EXPECT_LT(blended.border, 0.1 * hard.border);
}

TEST(Region, RefusesBadWeightsAndFaces) {
    const Mesh m = icosphere(1);
    std::vector<double> w(size_t(m.points.rows()), 0.5);
    w[3] = std::nan("");
    EXPECT_THROW(apply_filter_weighted(m.points, m.triangles, exaggerate(), w), Error);
    w[3] = 1.5;
    EXPECT_THROW(apply_filter_weighted(m.points, m.triangles, exaggerate(), w), Error);
    w.pop_back();
    EXPECT_THROW(apply_filter_weighted(m.points, m.triangles, exaggerate(), w), Error);
    Points far = m.points;
    far(0, 1) = std::numeric_limits<double>::infinity();  // a vertex the region would not touch
    EXPECT_THROW(apply_filter_weighted(far, m.triangles, exaggerate(), std::vector<double>(size_t(m.points.rows()), 0.0)),
                 Error);
    EXPECT_THROW(region_weight(m.points, m.triangles, {int(m.triangles.rows())}, 0.1), Error);
    EXPECT_THROW(region_weight(m.points, m.triangles, {0}, std::nan("")), Error);
}

// Through run_filter, as every adapter calls it: the table's region and blendWidth.
#include "filter_table.h"
#include "run_filter.h"

namespace {

RunOutput run_with(const std::string& filter, const ParameterValues& changes, const Mesh& m, const std::vector<int>& selected,
                   const std::vector<double>* quality = nullptr) {
    const FilterSpec& spec = *find_filter(filter);
    ParameterValues v = default_values(spec, !selected.empty());
    for (const auto& [name, value] : changes) v[name] = value;
    return run_filter(spec, v, RunInput{m.points, m.triangles, selected, {}, quality});
}

} // namespace

TEST(RegionRun, EveryFilterHasRegionAndBlendWidth) {
    for (const auto& f : filter_table()) {
        if (f.kind == FilterKind::Measure) continue;
        ASSERT_NE(f.parameter(param::region), nullptr) << f.name;
        EXPECT_EQ(f.parameter(param::region)->default_value, 0) << "whole mesh stays the default";
        ASSERT_NE(f.parameter(param::blend_width), nullptr) << f.name;
        EXPECT_EQ(f.parameter(param::blend_width)->default_value, 0) << "0 = auto";
    }
}

TEST(RegionRun, SelectedRegionWithAutoBandIsTheCoreWithTheFeatureRadius) {
    const Mesh m = bumpy_sphere();
    const std::vector<int> faces = faces_within(m, {0, 0, 1.1}, 0.3);
    // Frequency and region from the same selection.
    const RunOutput same = run_with("exaggerate", {{param::region, 1}}, m, faces);
    ASSERT_TRUE(same.feature);
    const double s1 = same.s1_used, width = std::sqrt(2 / s1);
    const Points expected = apply_filter_weighted(m.points, m.triangles, same.transfer,
                                                  region_weight(m.points, m.triangles, faces, width));
    EXPECT_TRUE(same.points == expected);
    bool logged = false;
    for (const auto& line : same.log) logged = logged || line.find("auto: the feature radius") != std::string::npos;
    EXPECT_TRUE(logged);
    // Typed frequency, selected region, given band.
    const RunOutput typed =
        run_with("exaggerate", {{param::region, 1}, {param::use_selection, 0}, {param::s1, 50}, {param::blend_width, 0.2}}, m, faces);
    EXPECT_EQ(typed.s1_used, 50);
    const Points typed_expected = apply_filter_weighted(m.points, m.triangles, typed.transfer,
                                                        region_weight(m.points, m.triangles, faces, 0.2));
    EXPECT_TRUE(typed.points == typed_expected);
}

TEST(RegionRun, QualityWeightOneIsWholeMeshZeroNothingAndBadQualityIsRefusedOrClamped) {
    Mesh m = torus(30, 20, 1.0, 0.35);
    perturb_radially(m, 0.02, 5);
    const auto n = size_t(m.points.rows());
    const RunOutput whole = run_with("exaggerate", {{param::s1, 40}}, m, {});
    const std::vector<double> ones(n, 1.0), zeros(n, 0.0);
    EXPECT_TRUE(run_with("exaggerate", {{param::s1, 40}, {param::region, 2}}, m, {}, &ones).points == whole.points);
    EXPECT_TRUE(run_with("exaggerate", {{param::s1, 40}, {param::region, 2}}, m, {}, &zeros).points == m.points);
    std::vector<double> big(n, 1.7);
    const RunOutput clamped = run_with("exaggerate", {{param::s1, 40}, {param::region, 2}}, m, {}, &big);
    EXPECT_TRUE(clamped.points == whole.points) << "1.7 is clamped to 1";
    bool logged = false;
    for (const auto& line : clamped.log) logged = logged || line.find("clamped") != std::string::npos;
    EXPECT_TRUE(logged);
    std::vector<double> nan = ones;
    nan[7] = std::nan("");
    EXPECT_NE(refusal_message([&] { run_with("exaggerate", {{param::region, 2}}, m, {}, &nan); }).find("NaN"), std::string::npos);
    EXPECT_NE(refusal_message([&] { run_with("exaggerate", {{param::region, 2}}, m, {}); }).find("no"), std::string::npos);
    EXPECT_NE(refusal_message([&] { run_with("exaggerate", {{param::region, 1}, {param::use_selection, 0}}, m, {}); })
                  .find("no faces are selected"),
              std::string::npos);
    EXPECT_NE(refusal_message([&] { run_with("polezero", {{param::region, 1}, {param::blend_width, -1}}, m, {0, 1}); })
                  .find("blendWidth"),
              std::string::npos);
}
