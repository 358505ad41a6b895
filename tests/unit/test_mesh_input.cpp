// Bad meshes: a clear refusal, or a repair that leaves the odd parts alone.
#include "core/filter.h"
#include "core/mesh_prep.h"
#include "core/shapes.h"
#include "run_filter.h"

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

TEST(MeshInput, OpenBoundariesAndNeedlesStillGiveFiniteResults) {
    Mesh g = grid(20, 1.0);
    g.points.col(2) = (g.points.col(0).array() * 7).sin() * 0.05;  // a wavy open sheet
    g.points(5, 0) += 0.0499;  // squeeze a vertex towards its neighbour: needle triangles
    const Points out = apply_filter(g.points, g.triangles, design_second_order({25, 50, 1, 1.1, 0}));
    EXPECT_TRUE(out.allFinite());
    // Lowpass removes the wave (s = 49 > s1) and keeps the sheet where it is.
    EXPECT_LT(out.col(2).cwiseAbs().maxCoeff(), g.points.col(2).cwiseAbs().maxCoeff());
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
