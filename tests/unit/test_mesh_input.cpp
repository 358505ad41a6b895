// Bad meshes: a clear refusal, or a repair that leaves the odd parts alone.
#include "core/filter/filter.h"
#include "core/mesh/mesh_prep.h"
#include "shapes.h"
#include "run_filter.h"
#include "spectral.h"

#include <gtest/gtest.h>

using namespace geofilter;

namespace {

std::string refusal(const Points& p, const Triangles& t) {
    try {
        apply_filter(p, t, design_second_order({25, 50, 1, 1.1, 0}));
    } catch (const Error& e) {
        return e.what();
    }
    return "accepted";
}

// The largest distance between `out` and the dense spectral filter (spectral.h) of the mesh
// (points, triangles), relative to the mesh's size.
double relative_distance_to_dense_filter(const Points& out, const Points& points, const Triangles& triangles,
                                         const TransferFunction& g) {
    const Points expected = reference::spectral_filter(reference::spectrum_of({points, triangles}), points, g);
    return (out - expected).rowwise().norm().maxCoeff() / reference::bbox_diagonal(points);
}

} // namespace

TEST(MeshInput, EmptyMeshesAndPointCloudsAreRefused) {
    EXPECT_NE(refusal(Points(0, 3), Triangles(0, 3)).find("no vertices"), std::string::npos);
    Points cloud(5, 3);
    cloud.setRandom();
    EXPECT_NE(refusal(cloud, Triangles(0, 3)).find("no faces"), std::string::npos);
}

TEST(MeshInput, NonFiniteCoordinatesAndBadIndicesAreRefusedByName) {
    Mesh m = icosphere(2);
    Points p = m.points;
    p(17, 1) = NAN;
    EXPECT_NE(refusal(p, m.triangles).find("vertex 17"), std::string::npos);
    p(17, 1) = INFINITY;
    EXPECT_NE(refusal(p, m.triangles).find("vertex 17"), std::string::npos);
    Triangles t = m.triangles;
    t(3, 2) = 100000;
    EXPECT_NE(refusal(m.points, t).find("face 3 refers to vertex 100000"), std::string::npos);
}

TEST(MeshInput, DegenerateFacesAreSkippedAndUnreferencedVerticesStayPut) {
    Mesh m = icosphere(3, 1.0);
    const Eigen::Index n = m.points.rows();
    Points p(n + 2, 3);
    p << m.points, Eigen::RowVector3d(5, 5, 5), Eigen::RowVector3d(6, 6, 6);  // two stray vertices
    Triangles t(m.triangles.rows() + 2, 3);
    t << m.triangles, Eigen::RowVector3i(0, 0, 1), Eigen::RowVector3i(2, 3, 3);  // two zero-area faces
    FilterReport report;
    const TransferFunction g = design_second_order({10, 25, 1, 30, 0});
    const Points out = apply_filter(p, t, g, {}, &report);
    EXPECT_EQ(out.row(n), p.row(n));
    EXPECT_EQ(out.row(n + 1), p.row(n + 1));
    EXPECT_EQ(report.active_vertices, n);
    ASSERT_EQ(report.warnings.size(), 2u);
    EXPECT_NE(report.warnings[0].find("2 zero-area face"), std::string::npos);
    EXPECT_NE(report.warnings[1].find("2 vertex"), std::string::npos);
    // The sphere itself is filtered as if the junk were not there.
    const Points clean = apply_filter(m.points, m.triangles, g);
    EXPECT_LT((out.topRows(n) - clean).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(MeshInput, OpenBoundariesAndNeedlesGiveTheExactFilter) {
    Mesh g = grid(20, 1.0);
    g.points.col(2) = (g.points.col(0).array() * 7).sin() * 0.05;  // a wavy open sheet
    g.points(5, 0) += 0.0499;  // squeeze a vertex towards its neighbour: needle triangles
    const TransferFunction lowpass = design_second_order({25, 50, 1, 1.1, 0});
    for (Solver solver : {Solver::Factored, Solver::JacobiPcg}) {
        FilterOptions options;
        options.solver = solver;
        const Points out = apply_filter(g.points, g.triangles, lowpass, options);
        ASSERT_TRUE(out.allFinite());
        // Needles make the system stiff, not different: the result is the exact filter.
        EXPECT_LT(relative_distance_to_dense_filter(out, g.points, g.triangles, lowpass), 1e-6) << solver_name(solver);
        // Lowpass removes the wave (s = 49 > s1) and keeps the sheet where it is.
        EXPECT_LT(out.col(2).cwiseAbs().maxCoeff(), g.points.col(2).cwiseAbs().maxCoeff());
    }
}

TEST(MeshInput, UseSelectionWithNothingSelectedIsRefusedAndNamesTheFix) {
    const Mesh m = icosphere(2);
    const FilterSpec& lowpass = *find_filter("GeoFilter: Lowpass");
    ParameterValues values = default_values(lowpass, true);
    const std::vector<int> none;
    try {
        run_filter(lowpass, values, {m.points, m.triangles, none, {}});
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no faces are selected"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("turn useSelection off"), std::string::npos);
    }
}

TEST(MeshInput, MeshTooLargeForTheMemoryBudgetIsRefusedUpFront) {
    const Mesh m = icosphere(3);
    FilterOptions options;
    options.memory_budget_bytes = 0.5 * estimated_filter_bytes(m.points.rows());
    try {
        apply_filter(m.points, m.triangles, design_second_order({25, 50, 1, 1.1, 0}), options);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("too large for the memory available"), std::string::npos) << e.what();
    }
    options.memory_budget_bytes = 2 * estimated_filter_bytes(m.points.rows());
    EXPECT_NO_THROW(apply_filter(m.points, m.triangles, design_second_order({25, 50, 1, 1.1, 0}), options));
}

TEST(MeshInput, NonManifoldEdgesAndVerticesAreFiltered) {
    // A fin: a third triangle on an edge of a sheet (non-manifold edge), and a second sheet
    // touching the first at one vertex only (non-manifold vertex).
    Mesh g = grid(6, 1.0);
    const Eigen::Index n = g.points.rows();
    Points p(n + 5, 3);
    p << g.points, Eigen::RowVector3d(0, 0, 0.4), Eigen::RowVector3d(1.0, 1.0, 0.2), Eigen::RowVector3d(1.0, 0.6, 0.1),
        Eigen::RowVector3d(0.6, 1.0, -0.1), Eigen::RowVector3d(0.9, 0.9, 0.3);
    Triangles t(g.triangles.rows() + 3, 3);
    const int corner = 48;  // (0.5, 0.5), a corner of the grid
    t << g.triangles, Eigen::RowVector3i(24, 25, int(n)),  // fin on the interior edge 24-25
        Eigen::RowVector3i(corner, int(n) + 2, int(n) + 1), Eigen::RowVector3i(corner, int(n) + 1, int(n) + 3);
    FilterReport report;
    const TransferFunction g3 = design_second_order({25, 60, 1, 3, 0});  // Fig. 10: moves it clearly
    const Points out = apply_filter(p, t, g3, {}, &report);
    ASSERT_TRUE(out.allFinite());
    EXPECT_EQ(out.row(n + 4), p.row(n + 4));  // unreferenced: stays
    // The rest is the exact filter of the mesh without that vertex (the cotangent Laplacian
    // sums over faces, so a fin or a pinch is just more terms).
    const Eigen::Index used = n + 4;
    EXPECT_LT(relative_distance_to_dense_filter(out.topRows(used), p.topRows(used), t, g3), 1e-6);
    EXPECT_GT((out - p).rowwise().norm().maxCoeff(), 1e-3);
}

TEST(MeshInput, DuplicatedVerticesAreReportedAndFilteredAsCut) {
    // An icosphere whose faces each have their own three corners (an unwelded STL).
    const Mesh s = icosphere(2, 1.0);
    Points p(s.triangles.rows() * 3, 3);
    Triangles t(s.triangles.rows(), 3);
    for (Eigen::Index f = 0; f < s.triangles.rows(); ++f)
        for (int k = 0; k < 3; ++k) {
            p.row(3 * f + k) = s.points.row(s.triangles(f, k));
            t(f, k) = int(3 * f + k);
        }
    FilterReport report;
    const TransferFunction g = design_second_order({25, 50, 1, 1.1, 0});
    const Points out = apply_filter(p, t, g, {}, &report);
    ASSERT_FALSE(report.warnings.empty());
    EXPECT_NE(report.warnings[0].find("duplicate the position"), std::string::npos) << report.warnings[0];
    EXPECT_NE(report.warnings[0].find(std::to_string(p.rows() - s.points.rows()) + " vertex"), std::string::npos);
    // What the warning says: the faces are not welded, each is filtered as its own surface,
    // which is the exact filter of the unwelded mesh (320 separate triangles) ...
    EXPECT_LT(relative_distance_to_dense_filter(out, p, t, g), 1e-6);
    // ... and visibly not the filter of the welded sphere.
    const Points welded = apply_filter(s.points, s.triangles, g);
    double apart = 0;
    for (Eigen::Index f = 0; f < t.rows(); ++f)
        for (int k = 0; k < 3; ++k) apart = std::max(apart, (out.row(3 * f + k) - welded.row(s.triangles(f, k))).norm());
    EXPECT_GT(apart, 1e-3);
}

TEST(MeshInput, SelectionSpanningSeveralComponentsIsMeasuredAsOneRegion) {
    // Two unit spheres 4 apart, both selected: one region of extent 6 x 2 x 2.
    const Mesh a = icosphere(2, 1.0);
    Mesh both;
    both.points.resize(2 * a.points.rows(), 3);
    both.points << a.points, (a.points.rowwise() + Eigen::RowVector3d(4, 0, 0));
    both.triangles.resize(2 * a.triangles.rows(), 3);
    both.triangles << a.triangles, (a.triangles.array() + int(a.points.rows())).matrix();
    std::vector<int> all(both.triangles.rows());
    for (size_t i = 0; i < all.size(); ++i) all[i] = int(i);
    const FeatureEllipsoid e = measure_feature(both.points, both.triangles, all);
    EXPECT_NEAR(e.radii[0], 3.0, 0.01);
    EXPECT_NEAR(e.radius, 1.0, 0.02);  // the round cross-section of the pair
    EXPECT_NEAR(e.center[0], 2.0, 1e-9);
}
