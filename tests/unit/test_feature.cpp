#include "core/feature.h"
#include "core/shapes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

using namespace geofilter;

namespace {

std::vector<int> all_faces(const Mesh& m) {
    std::vector<int> f(m.triangles.rows());
    for (size_t i = 0; i < f.size(); ++i) f[i] = static_cast<int>(i);
    return f;
}

// A rigid motion, so that the tests do not depend on the shape sitting at the origin.
void move(Mesh& m, const Eigen::Vector3d& axis, double angle, const Eigen::Vector3d& shift) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    for (Eigen::Index i = 0; i < m.points.rows(); ++i) m.points.row(i) = (r * m.points.row(i).transpose() + shift).transpose();
}

} // namespace

TEST(Feature, WholeSphereGivesTwoOverRSquared) {
    for (double r : {0.02, 0.5, 3.0}) {
        Mesh s = icosphere(3, r);
        move(s, {1, 2, 3}, 0.7, {5, -2, 1});
        const FeatureEllipsoid e = measure_feature(s.points, s.triangles, all_faces(s));
        EXPECT_NEAR(e.frequency(FeatureShape::Sphere), 2 / (r * r), 0.05 * 2 / (r * r)) << "r = " << r;
        EXPECT_NEAR(e.radius, r, 0.02 * r);
        EXPECT_LT((e.center - Eigen::Vector3d(5, -2, 1)).norm(), 1e-3 * r);
        EXPECT_NEAR(e.area, 4 * M_PI * r * r, 0.02 * 4 * M_PI * r * r);
    }
}

TEST(Feature, CylinderTubeGivesOneOverRSquared) {
    // A tube longer than wide: r comes from the two narrow radii.
    for (double r : {0.1, 2.0}) {
        Mesh c = cylinder(40, 48, r, 6 * r);
        move(c, {0, 1, 1}, 1.1, {-1, 4, 2});
        const FeatureEllipsoid e = measure_feature(c.points, c.triangles, all_faces(c));
        EXPECT_NEAR(e.frequency(FeatureShape::Cylinder), 1 / (r * r), 0.05 / (r * r)) << "r = " << r;
        EXPECT_NEAR(e.radii[0], 3 * r, 1e-6 * r);
        // The longest axis is the cylinder's axis.
        const Eigen::Vector3d axis = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0, 1, 1).normalized()) * Eigen::Vector3d::UnitZ();
        EXPECT_NEAR(std::abs(e.axes.col(0).dot(axis)), 1.0, 1e-6);
    }
}

TEST(Feature, ShortCylinderRingStillGivesItsRadius) {
    // A ring shorter than its diameter: the two wide radii are the round cross-section.
    const double r = 0.4;
    const Mesh c = cylinder(4, 64, r, 0.5 * r);
    const FeatureEllipsoid e = measure_feature(c.points, c.triangles, all_faces(c));
    EXPECT_NEAR(e.radius, r, 0.02 * r);
    EXPECT_NEAR(e.frequency(FeatureShape::Cylinder), 1 / (r * r), 0.05 / (r * r));
}

TEST(Feature, SphericalCapBumpUsesItsFootprintRadius) {
    // The upper half of a sphere: radii r, r, r/2 -> r; the frequency is the sphere's.
    const double r = 0.0563;  // the paper's dinosaur back-bone bump: s = 630
    const Mesh s = icosphere(4, r);
    std::vector<int> cap;
    for (Eigen::Index f = 0; f < s.triangles.rows(); ++f)
        if (s.points(s.triangles(f, 0), 2) >= -1e-12 && s.points(s.triangles(f, 1), 2) >= -1e-12 &&
            s.points(s.triangles(f, 2), 2) >= -1e-12)
            cap.push_back(static_cast<int>(f));
    const FeatureEllipsoid e = measure_feature(s.points, s.triangles, cap);
    EXPECT_NEAR(e.radii[2], r / 2, 0.05 * r);
    EXPECT_NEAR(e.frequency(FeatureShape::Sphere), 630, 0.05 * 630);
}

TEST(Feature, OneFaceIsAFlatEllipsoidAndEmptySelectionsAreRefused) {
    const Mesh g = grid(4, 1.0);
    const FeatureEllipsoid one = measure_feature(g.points, g.triangles, {0});
    EXPECT_EQ(one.radii[2], 0.0);
    EXPECT_GT(one.radius, 0.0);
    EXPECT_THROW(measure_feature(g.points, g.triangles, {}), Error);
    EXPECT_THROW(measure_feature(g.points, g.triangles, {999}), Error);
    Mesh flat = g;
    flat.points.col(1).setZero();  // every face collapses onto a line
    EXPECT_THROW(measure_feature(flat.points, flat.triangles, {0, 1}), Error);
}
