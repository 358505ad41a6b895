// Filters on a point cloud through run_filter: the same closed form as on a mesh (a sphere of
// radius r scaled by G(2/r^2)), the feature from selected points equal to the one from the
// faces over them, the region leaving everything outside it untouched, and refusals that name
// the problem with nothing filtered.
#include "core/operators/point_cloud_laplace.h"
#include "run_filter.h"
#include "refusal.h"
#include "shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <string>

using namespace geofilter;

namespace {

double mean_radius(const Points& p) { return p.rowwise().norm().mean(); }

const Triangles no_faces(0, 3);
const std::vector<int> nothing;

RunOutput run_on_cloud(const std::string& name, const Points& cloud, ParameterValues values,
                       std::vector<int> selected_points = {}) {
    const FilterSpec& spec = *find_filter(name);
    ParameterValues v = default_values(spec, !selected_points.empty());
    for (const auto& [key, value] : values) v[key] = value;
    return run_filter(spec, v, RunInput{cloud, no_faces, nothing, {}, nullptr, nullptr, {}, {}, std::move(selected_points)});
}

bool log_has(const RunOutput& out, const std::string& text) {
    for (const auto& line : out.log)
        if (line.find(text) != std::string::npos) return true;
    return false;
}

} // namespace

// Section 5's sphere test on a cloud: the coordinate functions are eigenvectors of the cloud's
// operator with s = 2/r^2 (to its accuracy, ~1 %), so the filter scales the sphere by G there.
TEST(CloudFilter, SphereCloudScalesByGAtTwoOverRSquared) {
    const double r = 0.5;
    const Points cloud = fibonacci_sphere(3000, r);
    for (const std::string name : {"lowpass", "exaggerate", "butterworth"}) {
        const RunOutput out = run_on_cloud(name, cloud, {{param::radius, 0.3}});
        const double expected = out.transfer(2 / (r * r)), measured = mean_radius(out.points) / r;
        std::cout << name << ": mean radius ratio " << measured << ", G(2/r^2) " << expected << "\n";
        EXPECT_NEAR(measured, expected, 0.01 * std::abs(expected)) << name;
        EXPECT_TRUE(log_has(out, "point cloud: 3000 points, k = 30 neighbours (fans among the nearest 15), ")) << name;
        EXPECT_TRUE(log_has(out, " local triangles (the cloud's Laplacian)")) << name;
        ASSERT_EQ(out.normals.rows(), cloud.rows());
        EXPECT_GT((out.normals.array() * cloud.array()).rowwise().sum().minCoeff(), 0) << "normals point outwards";
    }
}

// A cap of the sphere selected as points measures as the faces over the same vertices.
TEST(CloudFilter, SelectedPointsMeasureLikeTheSelectedFaces) {
    const Mesh s = icosphere(4, 1.0);
    for (double height : {0.5, 0.8}) {  // caps of half-angle 60 and 37 degrees
        std::vector<int> points, faces;
        for (Eigen::Index i = 0; i < s.points.rows(); ++i)
            if (s.points(i, 2) >= height) points.push_back(static_cast<int>(i));
        for (Eigen::Index f = 0; f < s.triangles.rows(); ++f)
            if (s.points(s.triangles(f, 0), 2) >= height && s.points(s.triangles(f, 1), 2) >= height &&
                s.points(s.triangles(f, 2), 2) >= height)
                faces.push_back(static_cast<int>(f));
        const FeatureEllipsoid by_faces = measure_feature(s.points, s.triangles, faces);
        const PointCloudLaplacian cloud = point_cloud_laplacian(s.points);
        const FeatureEllipsoid by_points = measure_feature_of_points(s.points, points, cloud.laplacian.mass);
        std::cout << "cap z >= " << height << ": faces r = " << by_faces.radius << ", points r = " << by_points.radius
                  << "\n";
        EXPECT_NEAR(by_points.radius, by_faces.radius, 0.03 * by_faces.radius);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(by_points.radii[k], by_faces.radii[k], 0.03 * by_faces.radii[0]);
        EXPECT_NEAR(std::abs(by_points.axes.col(2).dot(Eigen::Vector3d::UnitZ())), 1.0, 1e-3);
        EXPECT_EQ(by_points.point_count, static_cast<int>(points.size()));

        // Through run_filter: Measure on the cloud, and the lowpass's frequency from it.
        const RunOutput measured = run_on_cloud("measure", s.points, {}, points);
        EXPECT_NEAR(measured.feature->radius, by_points.radius, 1e-12);
        EXPECT_TRUE(log_has(measured, std::to_string(points.size()) + " selected points"));
        const RunOutput lowpassed = run_on_cloud("lowpass", s.points, {}, points);
        EXPECT_NEAR(lowpassed.s1_used, 2 / (by_points.radius * by_points.radius), 1e-9 * lowpassed.s1_used);
    }
}

// Region = selected: the selected points and a band around them are filtered, every other
// point stays bit for bit.
TEST(CloudFilter, RegionOfSelectedPointsLeavesTheRestExactly) {
    Mesh s = icosphere(4, 1.0);
    perturb_radially(s, 0.02, 3);
    std::vector<int> cap;
    for (Eigen::Index i = 0; i < s.points.rows(); ++i)
        if (s.points(i, 2) >= 0.7) cap.push_back(static_cast<int>(i));
    const RunOutput out = run_on_cloud("lowpass", s.points, {{param::region, 1}, {param::blend_width, 0.2},
                                                             {param::use_selection, 0}, {param::radius, 0.2}},
                                       cap);
    int moved_outside = 0, moved_inside = 0;
    for (Eigen::Index i = 0; i < s.points.rows(); ++i) {
        const bool moved = out.points.row(i) != s.points.row(i);
        if (s.points(i, 2) < 0.3) moved_outside += moved;
        if (s.points(i, 2) >= 0.75) moved_inside += moved;
    }
    EXPECT_EQ(moved_outside, 0);
    EXPECT_GT(moved_inside, 50);
}

TEST(CloudFilter, BadCloudsAreRefusedNamingTheProblem) {
    const Points cloud = fibonacci_sphere(500, 1.0);
    Points doubled(cloud.rows() + 1, 3);
    doubled << cloud, cloud.row(7);
    EXPECT_NE(refusal_message([&] { run_on_cloud("lowpass", doubled, {{param::radius, 0.3}}); }).find("duplicate"),
              std::string::npos);
    EXPECT_NE(refusal_message([&] { run_on_cloud("lowpass", cloud.topRows(20), {{param::radius, 0.3}}); }).find("has 20 points"),
              std::string::npos);
    const FilterSpec& lowpass = *find_filter("lowpass");
    const std::vector<int> faces{0, 1};
    EXPECT_NE(refusal_message([&] {
                  run_filter(lowpass, default_values(lowpass, true), RunInput{cloud, no_faces, faces, {}});
              }).find("point cloud (points and no faces), yet 2 faces"),
              std::string::npos);
    EXPECT_NE(refusal_message([&] { run_on_cloud("lowpass", cloud, {{param::use_selection, 1}}); }).find("no points of the cloud"),
              std::string::npos);
    EXPECT_NE(refusal_message([&] { run_on_cloud("lowpass", cloud, {{param::radius, 0.3}, {param::fix_boundary, 1}}); })
                  .find("fixBoundary"),
              std::string::npos);
    EXPECT_NE(refusal_message([&] { run_on_cloud("lowpass", cloud, {{param::radius, 0.3}}, {0, 100000}); }).find("out of range"),
              std::string::npos);
    EXPECT_NE(refusal_message([&] { run_on_cloud("lowpass", cloud, {{param::radius, 0.3}, {param::region, 1}}); })
                  .find("none are selected"),
              std::string::npos);
    EXPECT_NE(refusal_message([&] { run_on_cloud("butterworth", cloud, {{param::radius, 0.3}, {param::laplace_operator, 2}}); })
                  .find("intrinsic Delaunay"),
              std::string::npos);
}

// An outlier far from the surface is filtered (pulled towards it), with a warning in the log.
TEST(CloudFilter, IsolatedPointIsWarnedAbout) {
    Points cloud = fibonacci_sphere(800, 1.0);
    cloud.row(0) = Eigen::RowVector3d(0, 0, 4);
    const RunOutput out = run_on_cloud("lowpass", cloud, {{param::radius, 0.5}});
    EXPECT_TRUE(log_has(out, "1 isolated point(s) (point 0 first)"));
}
