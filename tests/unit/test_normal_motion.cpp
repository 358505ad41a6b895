// keep_normal_motion: a smoother's sideways drift is dropped, its motion across the surface
// kept, and no face ends up turned further than the limit from the smoother's.
#include "core/denoise/normal_motion.h"
#include "core/mesh/surface_measures.h"
#include "shapes.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace geofilter;

namespace {

using reference::rms_distance;

Eigen::RowVector3d face_normal(const Points& p, const Triangles& t, Eigen::Index f) {
    const Eigen::RowVector3d a = p.row(t(f, 0));
    return (p.row(t(f, 1)) - a).cross(p.row(t(f, 2)) - a).normalized();
}

double largest_turn_degrees(const Points& a, const Points& b, const Triangles& t) {
    double largest = 0;
    for (Eigen::Index f = 0; f < t.rows(); ++f)
        largest = std::max(largest, std::acos(std::clamp(face_normal(a, t, f).dot(face_normal(b, t, f)), -1.0, 1.0)));
    return largest * 180 / M_PI;
}

Points rotated_about_z(const Points& p, double angle) {
    Eigen::Matrix3d r;
    r << std::cos(angle), -std::sin(angle), 0, std::sin(angle), std::cos(angle), 0, 0, 0, 1;
    return p * r.transpose();
}

} // namespace

// A unit sphere noised along its radii, "smoothed" into the exact sphere turned by 2 degrees
// about z: a smoother that removed the noise but slid every vertex sideways. Kept along the
// smoothed normals only, the motion brings each vertex back onto the sphere where the noise
// found it, i.e. to the truth, up to the turn's second order and the polyhedron's normals;
// and each vertex moved along its smoothed normal only.
TEST(NormalMotion, ASidewaysDriftIsDroppedAndTheMotionAcrossKept) {
    const Mesh m = icosphere(4, 1.0);
    std::mt19937 random(3);
    std::normal_distribution<double> gauss(0.0, 0.01);
    const Eigen::MatrixXd radial = m.points.rowwise().normalized();
    Points noisy = m.points;
    for (Eigen::Index v = 0; v < noisy.rows(); ++v) noisy.row(v) += gauss(random) * radial.row(v);
    const Points smoothed = rotated_about_z(m.points, 2 * M_PI / 180);

    NormalMotionReport report;
    const Points out = keep_normal_motion(noisy, smoothed, m.triangles, normal_motion_max_turn_degrees, &report);
    EXPECT_EQ(report.vertices_projected, m.points.rows());
    EXPECT_EQ(report.vertices_kept_smoothed, 0);
    EXPECT_GT(rms_distance(smoothed, m.points), 0.02);  // the drift the test is about
    EXPECT_LT(rms_distance(out, m.points), 0.05 * rms_distance(smoothed, m.points));
    const Eigen::MatrixXd n = vertex_normals(smoothed, m.triangles);
    for (Eigen::Index v = 0; v < out.rows(); ++v) {
        const Eigen::RowVector3d motion = out.row(v) - noisy.row(v), normal = n.row(v);
        ASSERT_LT(motion.cross(normal).norm(), 1e-12) << v;
    }
}

// A vertex of a flat grid pushed 1.5 cells sideways (its faces folded), smoothed back to its
// place: along the normal (z) there is nothing to move, so the projection alone would keep the
// fold. The faces turned past the limit send their vertices to the smoother's positions; the
// rest of the sheet is projected (here: unchanged) and nothing ends up turned past the limit.
TEST(NormalMotion, FacesTurnedPastTheLimitTakeTheSmoothersPositions) {
    const Mesh g = grid(10, 1.0);
    const Eigen::Index centre = 5 * 11 + 5;
    Points noisy = g.points;
    noisy(centre, 0) += 0.15;
    NormalMotionReport report;
    const Points out = keep_normal_motion(noisy, g.points, g.triangles, normal_motion_max_turn_degrees, &report);
    EXPECT_GT(largest_turn_degrees(noisy, g.points, g.triangles), 90);  // the input is folded
    EXPECT_LE(largest_turn_degrees(out, g.points, g.triangles), normal_motion_max_turn_degrees + 1e-9);
    EXPECT_TRUE(out.row(centre) == g.points.row(centre));
    EXPECT_GE(report.vertices_kept_smoothed, 1);
    EXPECT_GE(report.rounds, 2);
    EXPECT_EQ(report.vertices_projected + report.vertices_kept_smoothed, g.points.rows());
    EXPECT_LT((out - g.points).cwiseAbs().maxCoeff(), 1e-15);
}

// Sideways drift large enough to turn many faces: whatever the projection does, no face of
// the result is turned past the limit from the smoother's, and the vertices that were sent
// back are exactly the smoother's.
TEST(NormalMotion, NoFaceEndsTurnedPastTheLimit) {
    const Mesh m = icosphere(3, 1.0);
    const double h = mean_edge_length(m.points, m.triangles);
    std::mt19937 random(8);
    std::normal_distribution<double> gauss(0.0, 0.6 * h);
    Points smoothed = m.points;
    for (Eigen::Index v = 0; v < smoothed.rows(); ++v)
        for (int k = 0; k < 3; ++k) smoothed(v, k) += gauss(random);
    NormalMotionReport report;
    const Points out = keep_normal_motion(m.points, smoothed, m.triangles, normal_motion_max_turn_degrees, &report);
    EXPECT_GT(report.vertices_kept_smoothed, 0);
    EXPECT_GT(report.vertices_projected, 0);
    EXPECT_LE(largest_turn_degrees(out, smoothed, m.triangles), normal_motion_max_turn_degrees + 1e-9);
    int equal = 0;
    for (Eigen::Index v = 0; v < out.rows(); ++v) equal += out.row(v) == smoothed.row(v);
    EXPECT_GE(equal, report.vertices_kept_smoothed);
}

// A vertex in no face has no normal: it takes the smoother's position.
TEST(NormalMotion, AVertexInNoFaceTakesTheSmoothersPosition) {
    Mesh m = icosphere(2, 1.0);
    m.points.conservativeResize(m.points.rows() + 1, 3);
    m.points.bottomRows(1) << 5, 5, 5;
    Points smoothed = 0.99 * m.points;
    NormalMotionReport report;
    const Points out = keep_normal_motion(m.points, smoothed, m.triangles, normal_motion_max_turn_degrees, &report);
    EXPECT_TRUE(out.bottomRows(1) == smoothed.bottomRows(1));
    EXPECT_EQ(report.vertices_kept_smoothed, 1);
}
