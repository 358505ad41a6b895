// restore_volume: one offset along the normals per closed component gives it back its volume.
// Checked on spheres, whose volume and offset have closed forms.
#include "core/denoise/volume.h"
#include "shapes.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace geofilter;

namespace {


double sphere_volume(const Points& p, const Triangles& t) {
    double v = 0;
    for (Eigen::Index f = 0; f < t.rows(); ++f) v += p.row(t(f, 0)).dot(p.row(t(f, 1)).cross(p.row(t(f, 2)))) / 6;
    return v;
}

} // namespace

// A sphere shrunk to radius 0.97 is pushed back out by 0.03 along its normals: every vertex
// returns to radius 1 up to the polyhedron's own deviation from the sphere.
TEST(Volume, AShrunkSphereComesBackToItsRadius) {
    const Mesh m = icosphere(5, 1.0);
    const Points shrunk = 0.97 * m.points;
    VolumeRestoreReport report;
    const Points out = restore_volume(m.points, shrunk, m.triangles, &report);
    EXPECT_EQ(report.closed_components, 1);
    EXPECT_NEAR(report.largest_change, 1 - std::pow(0.97, 3), 1e-9);
    EXPECT_NEAR(report.largest_offset, 0.03, 1e-3);
    EXPECT_NEAR(sphere_volume(out, m.triangles) / sphere_volume(m.points, m.triangles), 1.0, 1e-9);
    EXPECT_LT((out.rowwise().norm().array() - 1.0).abs().maxCoeff(), 2e-4);
    EXPECT_NEAR(sphere_volume(m.points, m.triangles), 4 * M_PI / 3, 0.01);  // the test's own premise
}

// Faces wound inwards: the volume is negative, the normals point in; the offset still
// restores it (outwards in space).
TEST(Volume, InwardWindingIsRestoredToo) {
    Mesh m = icosphere(4, 1.0);
    m.triangles.col(1).swap(m.triangles.col(2));
    const Points out = restore_volume(m.points, 0.95 * m.points, m.triangles);
    EXPECT_NEAR(sphere_volume(out, m.triangles) / sphere_volume(m.points, m.triangles), 1.0, 1e-9);
    EXPECT_GT(out.rowwise().norm().mean(), 0.999);
}

// Only closed components move: next to a shrunk sphere, an open sheet (the same sheet in the
// input and the smoothed mesh, moved or not) stays exactly where the smoother put it.
TEST(Volume, OpenComponentsAndLooseVerticesStayPut) {
    const Mesh s = icosphere(3, 1.0);
    Mesh g = grid(8, 1.0);
    Mesh both;
    const Eigen::Index ns = s.points.rows(), ng = g.points.rows();
    both.points.resize(ns + ng + 1, 3);
    both.points << s.points, g.points.rowwise() + Eigen::RowVector3d(3, 0, 0), Eigen::RowVector3d(9, 9, 9);
    both.triangles.resize(s.triangles.rows() + g.triangles.rows(), 3);
    both.triangles << s.triangles, g.triangles.array() + static_cast<int>(ns);
    Points smoothed = both.points;
    smoothed.topRows(ns) *= 0.9;
    smoothed.middleRows(ns, ng).col(2).array() += 0.1;  // the sheet moved: its "volume" must not pull it back
    VolumeRestoreReport report;
    const Points out = restore_volume(both.points, smoothed, both.triangles, &report);
    EXPECT_EQ(report.closed_components, 1);
    EXPECT_TRUE(out.bottomRows(ng + 1) == smoothed.bottomRows(ng + 1));
    EXPECT_NEAR(sphere_volume(out.topRows(ns), s.triangles) / sphere_volume(s.points, s.triangles), 1.0, 1e-9);
}

// A scan in world or scanner coordinates lies far from the origin. The volume it encloses
// does not depend on where it lies, and neither must the offset that restores it: the same
// shrunk sphere a million radii away comes back to its radius about its own centre.
TEST(Volume, AFarAwaySphereIsRestoredAsAtTheOrigin) {
    const Mesh m = icosphere(5, 1.0);
    const Eigen::RowVector3d far(1e6, -2e6, 3e6);
    const Points placed = m.points.rowwise() + far;
    const Points shrunk = (0.97 * m.points).rowwise() + far;
    VolumeRestoreReport report;
    const Points out = restore_volume(placed, shrunk, m.triangles, &report);
    EXPECT_NEAR(report.largest_change, 1 - std::pow(0.97, 3), 1e-6);
    EXPECT_NEAR(report.largest_offset, 0.03, 1e-3);
    EXPECT_LT(((out.rowwise() - far).rowwise().norm().array() - 1.0).abs().maxCoeff(), 2e-4);
}
