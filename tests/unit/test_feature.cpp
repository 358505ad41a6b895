#include "core/feature/feature.h"
#include "shapes.h"

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

// The faces of a sphere centred at the origin with all three vertices at z >= 0: a cap.
std::vector<int> upper_half_faces(const Mesh& s) {
    std::vector<int> cap;
    for (Eigen::Index f = 0; f < s.triangles.rows(); ++f)
        if (s.points(s.triangles(f, 0), 2) >= -1e-12 && s.points(s.triangles(f, 1), 2) >= -1e-12 &&
            s.points(s.triangles(f, 2), 2) >= -1e-12)
            cap.push_back(static_cast<int>(f));
    return cap;
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
    const std::vector<int> cap = upper_half_faces(s);
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

TEST(Feature, RadiusRuleIsContinuousInTheRadii) {
    // The old rule (mean of the two most similar radii) jumped from r = 1.0 at
    // (1.5, 0.5, 0.16) to r = 0.335 at (1.5, 0.5, 0.17).
    const double at_016 = feature_radius({1.5, 0.5, 0.16}), at_017 = feature_radius({1.5, 0.5, 0.17});
    EXPECT_LT(std::abs(at_016 - at_017), 0.02 * at_016);
    // Sweep each aspect ratio finely: a step of 0.1 % in one radius moves r by at most ~0.1 %
    // of the largest radius (the rule is Lipschitz away from degenerate ellipsoids).
    for (double r2 : {0.2, 0.5, 0.9, 1.0}) {
        double previous = feature_radius({1.0, r2, 0.01 * r2});
        for (double t = 0.01; t <= 1.0; t += 0.001) {
            const double r = feature_radius({1.0, r2, t * r2});
            EXPECT_LT(std::abs(r - previous), 2e-3) << "r2 = " << r2 << ", r3/r2 = " << t;
            previous = r;
        }
    }
    for (double r3 : {0.05, 0.3}) {
        double previous = feature_radius({r3 / 0.3, r3, r3 * 0.999});
        for (double r1 = r3 / 0.3; r1 >= r3; r1 *= 0.999) {
            const double r = feature_radius({r1, r3, r3 * 0.999});
            EXPECT_LT(std::abs(r - previous), 2e-3 * r1) << "r1 = " << r1;
            previous = r;
        }
    }
}

TEST(Feature, RadiusRuleKeepsTheShapesItIsFor) {
    EXPECT_DOUBLE_EQ(feature_radius({0.7, 0.7, 0.7}), 0.7);     // sphere
    EXPECT_DOUBLE_EQ(feature_radius({0.7, 0.7, 0.35}), 0.7);    // cap: height r/2
    EXPECT_DOUBLE_EQ(feature_radius({3.0, 0.2, 0.2}), 0.2);     // tube
    EXPECT_DOUBLE_EQ(feature_radius({0.7, 0.7, 0.0}), 0.7);     // flat disc
    EXPECT_EQ(feature_radius({1.0, 0.0, 0.0}), 0.0);            // a line: no radius (refused)
}

TEST(Feature, GeoreferencedCoordinatesGiveTheSameFrequency) {
    // A 5 cm bump on a scan stored in UTM metres: raw second moments (~1e13) would cancel
    // the feature's (~1e-3) to rounding noise.
    const double r = 0.05;
    const Mesh s = icosphere(4, r);
    const std::vector<int> cap = upper_half_faces(s);
    const FeatureEllipsoid local = measure_feature(s.points, s.triangles, cap);
    Mesh far = s;
    far.points.rowwise() += Eigen::RowVector3d(5e5, 4e6, 1e2);
    const FeatureEllipsoid utm = measure_feature(far.points, far.triangles, cap);
    EXPECT_NEAR(utm.frequency(FeatureShape::Sphere), local.frequency(FeatureShape::Sphere),
                1e-6 * local.frequency(FeatureShape::Sphere));
    EXPECT_LT((utm.center - Eigen::Vector3d(5e5, 4e6, 1e2) - local.center).norm(), 1e-6 * r);
}

TEST(Feature, ASelectionSplitInPartsMeasuresAsAWhole) {
    // geofilter-mpi's ranks each hold part of the selection: their moments add up and their
    // extents combine. A cap of radius 0.5 (s = 2/r^2 = 8 on a whole sphere), about another
    // origin than the whole measurement's, in three interleaved parts.
    Mesh s = icosphere(3, 0.5);
    const std::vector<int> cap = upper_half_faces(s);
    move(s, {1, -1, 2}, 0.4, {3, 1, -2});
    const FeatureEllipsoid whole = measure_feature(s.points, s.triangles, cap);
    std::vector<int> parts[3];
    for (size_t i = 0; i < cap.size(); ++i) parts[i % 3].push_back(cap[i]);
    const Eigen::Vector3d origin = s.points.row(s.triangles(cap.back(), 2)).transpose();
    SelectionMoments total;
    for (const auto& part : parts) {
        const SelectionMoments m = selection_moments(s.points, s.triangles, part, origin);
        total.area += m.area;
        total.first += m.first;
        total.second += m.second;
        total.face_count += m.face_count;
    }
    const FeatureFrame frame = feature_frame(total);
    Eigen::Vector3d low = Eigen::Vector3d::Constant(INFINITY), high = Eigen::Vector3d::Constant(-INFINITY);
    for (const auto& part : parts) extend_in_frame(frame, origin, s.points, s.triangles, part, low, high);
    const FeatureEllipsoid split = ellipsoid_in_frame(total, frame, origin, low, high);
    EXPECT_EQ(split.face_count, static_cast<int>(cap.size()));
    EXPECT_NEAR(split.area, whole.area, 1e-12);
    EXPECT_NEAR(split.radius, whole.radius, 1e-12);
    EXPECT_LT((split.center - whole.center).norm(), 1e-12);
    EXPECT_LT((split.radii - whole.radii).norm(), 1e-12);
    // Half a sphere of radius 0.5: its two wide extents are the radius.
    EXPECT_NEAR(split.radius, 0.5, 0.02);
}
