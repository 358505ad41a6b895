// The point-cloud Laplacian: the sphere's spectrum in the mesh operator's units, the same
// lowpass as the mesh operator on the mesh's own vertices, consistent normals, exact linear
// precision on a plane, and refusals that name the problem.
#include "core/filter/filter.h"
#include "core/operators/point_cloud_laplace.h"
#include "refusal.h"
#include "shapes.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <Eigen/SparseCholesky>

#include <cmath>
#include <iostream>
#include <random>

using namespace geofilter;

namespace {

// Points spread evenly over the sphere of `radius`: the Fibonacci lattice.
// The lowest `count` eigenvalues of K x = s M x: inverse subspace iteration on a block of
// `block` vectors (one sparse LDL^T of K + shift M, positive definite since K is positive
// semi-definite), kept M-orthonormal by a QR in the frame M^1/2 x, then Rayleigh-Ritz. The
// error of eigenvalue i shrinks by (s_i + shift) / (s_block + shift) per iteration.
Eigen::VectorXd lowest_eigenvalues(const Laplacian& l, int count, int block, int iterations) {
    const Eigen::Index n = l.mass.size();
    const SparseMatrix m = SparseMatrix(l.mass.asDiagonal());
    const double shift = 1e-4 * l.stiffness.diagonal().sum() / l.mass.sum();
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(SparseMatrix(l.stiffness + shift * m));
    EXPECT_EQ(ldlt.info(), Eigen::Success);
    const Eigen::VectorXd sqrt_mass = l.mass.cwiseSqrt();
    std::mt19937 rng(5);
    std::normal_distribution<double> normal;
    Eigen::MatrixXd x(n, block);
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = normal(rng);
    for (int it = 0; it < iterations; ++it) {
        x = ldlt.solve(m * x);
        const Eigen::MatrixXd y = sqrt_mass.asDiagonal() * x;
        const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(y).householderQ() * Eigen::MatrixXd::Identity(n, block);
        x = sqrt_mass.cwiseInverse().asDiagonal() * q;
    }
    return reference::generalized_eigenvalues(x.transpose() * l.stiffness * x, x.transpose() * m * x).head(count);
}

double rayleigh_quotient(const Laplacian& l, const Eigen::VectorXd& f) {
    return f.dot(l.stiffness * f) / f.dot(l.mass.asDiagonal() * f);
}

// Area of the convex hull of the xy coordinates, by gift wrapping (not the core's hull).
double convex_hull_area(const Points& p) {
    Eigen::Index start = 0;
    for (Eigen::Index i = 1; i < p.rows(); ++i)
        if (p(i, 0) < p(start, 0)) start = i;
    auto turn = [&](Eigen::Index o, Eigen::Index a, Eigen::Index b) {
        return (p(a, 0) - p(o, 0)) * (p(b, 1) - p(o, 1)) - (p(a, 1) - p(o, 1)) * (p(b, 0) - p(o, 0));
    };
    double twice_area = 0;
    Eigen::Index current = start;
    do {
        Eigen::Index next = current == 0 ? 1 : 0;
        for (Eigen::Index i = 0; i < p.rows(); ++i)
            if (i != current && turn(current, next, i) < 0) next = i;  // i lies right of current -> next
        twice_area += p(current, 0) * p(next, 1) - p(next, 0) * p(current, 1);
        current = next;
    } while (current != start);
    return 0.5 * std::abs(twice_area);
}

std::string refusal(const Points& points, const PointCloudOptions& options = {}) {
    return refusal_message([&] { point_cloud_laplacian(points, options); });
}

} // namespace

TEST(PointCloudLaplacian, SphereSpectrumInTheMeshOperatorsUnits) {
    const double r = 2.0;
    const Points p = fibonacci_sphere(10000, r);
    const PointCloudLaplacian cloud = point_cloud_laplacian(p);
    const Laplacian& l = cloud.laplacian;

    // The division by 3: the soup covers the sphere three times, M must cover it once.
    EXPECT_NEAR(l.mass.sum() / (4 * M_PI * r * r), 1.0, 0.01);
    EXPECT_GT(l.mass.minCoeff(), 0.0);
    EXPECT_LT((l.stiffness * Eigen::VectorXd::Ones(p.rows())).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LT((SparseMatrix(l.stiffness.transpose()) - l.stiffness).cwiseAbs().sum(), 1e-10 * l.stiffness.cwiseAbs().sum());

    // s = l (l + 1) / r^2: 0 once, 2/r^2 three times, 6/r^2 five times, then 12/r^2. A block of
    // 16 holds l <= 3, so the 6/r^2 modes converge like (6/20)^iterations.
    const Eigen::VectorXd s = lowest_eigenvalues(l, 10, 16, 40) * r * r;
    std::cout << "sphere r = 2, 10k points, eigenvalues * r^2: " << s.transpose() << "\n";
    EXPECT_NEAR(s[0], 0.0, 1e-6);
    for (int i = 1; i <= 3; ++i) EXPECT_NEAR(s[i] / 2.0, 1.0, 0.02) << "eigenvalue " << i;
    for (int i = 4; i <= 8; ++i) EXPECT_NEAR(s[i] / 6.0, 1.0, 0.02) << "eigenvalue " << i;
    EXPECT_NEAR(s[9] / 12.0, 1.0, 0.05);

    for (int axis = 0; axis < 3; ++axis)
        EXPECT_NEAR(rayleigh_quotient(l, p.col(axis)) * r * r / 2.0, 1.0, 0.02) << "axis " << axis;

    // Normals: unit and outward.
    const Eigen::VectorXd outward = (cloud.normals.cwiseProduct(p / r)).rowwise().sum();
    EXPECT_GT(outward.minCoeff(), 0.99);
}

// The vertices of a Delaunay mesh as a cloud: every fan is the vertex's star in the mesh, so
// the soup is the mesh three times over and the operator is the mesh's to rounding.
TEST(PointCloudLaplacian, VerticesOfADelaunayMeshGiveTheMeshOperator) {
    const Mesh m = icosphere(4, 1.5);
    const PointCloudLaplacian cloud = point_cloud_laplacian(m.points);
    const Laplacian mesh_operator = cotan_laplacian(m.points, m.triangles);
    EXPECT_EQ(cloud.local_triangles.rows(), 3 * m.triangles.rows());
    EXPECT_LT((cloud.laplacian.stiffness - mesh_operator.stiffness).cwiseAbs().sum(),
              1e-12 * mesh_operator.stiffness.cwiseAbs().sum());
    EXPECT_LT((cloud.laplacian.mass - mesh_operator.mass).cwiseAbs().maxCoeff(), 1e-12 * mesh_operator.mass.maxCoeff());
}

// The same surface as a mesh and as the mesh's vertices, on a mesh whose triangulation is not
// the one the cloud picks (vertices slid along the sphere, obtuse triangles): a lowpass with
// the cloud's operator moves the points as the mesh's cotangent operator moves them.
TEST(PointCloudLaplacian, LowpassOfAMeshsVerticesMatchesTheMeshOperator) {
    Mesh m = icosphere(5, 1.0);
    const double edge = 1.1 / 32;  // about the mean edge length
    std::mt19937 rng(11);
    std::normal_distribution<double> slide(0.0, 0.25 * edge);
    std::uniform_real_distribution<double> noise(-1.0, 1.0);
    for (Eigen::Index i = 0; i < m.points.rows(); ++i) {
        const Eigen::RowVector3d u =
            (m.points.row(i) + Eigen::RowVector3d(slide(rng), slide(rng), slide(rng))).normalized();
        const double bumps = 0.06 * std::sin(5 * u.x()) * std::sin(4 * u.y() + 1) * std::cos(3 * u.z());
        m.points.row(i) = u * (1.0 + bumps + 0.004 * noise(rng));
    }
    const PointCloudLaplacian cloud = point_cloud_laplacian(m.points);
    const Laplacian mesh_operator = cotan_laplacian(m.points, m.triangles);
    // The comparison means something only if the two operators are built on different triangles.
    ASSERT_GT((cloud.laplacian.stiffness - mesh_operator.stiffness).cwiseAbs().sum(),
              0.05 * mesh_operator.stiffness.cwiseAbs().sum());

    // G(s) = 40 * 60 / ((s + 40) (s + 60)): keeps degrees up to about 4, halves degree 6, and
    // removes most of the noise.
    const TransferFunction lowpass = design_pole_zero({1.0, {}, {40.0, 60.0}});
    const Points by_mesh = apply_filter(m.points, m.triangles, lowpass);
    const Points by_cloud = apply_filter(m.points, cloud.local_triangles, lowpass);
    const double moved = std::sqrt((by_mesh - m.points).rowwise().squaredNorm().mean());
    const double apart = std::sqrt((by_cloud - by_mesh).rowwise().squaredNorm().mean());
    std::cout << "slid bumpy icosphere (10242 vertices): lowpass moved the mesh by " << moved
              << " RMS; cloud - mesh " << apart << " RMS (" << 100 * apart / moved << " %)\n";
    EXPECT_GT(moved, 0.01);  // the filter does something worth comparing
    EXPECT_LT(apart, 0.05 * moved);

    // The operators themselves agree on smooth functions.
    for (int axis = 0; axis < 3; ++axis) {
        const Eigen::VectorXd f = m.points.col(axis);
        EXPECT_NEAR(rayleigh_quotient(cloud.laplacian, f) / rayleigh_quotient(mesh_operator, f), 1.0, 0.05);
    }
    EXPECT_NEAR(cloud.laplacian.mass.sum() / mesh_operator.mass.sum(), 1.0, 0.01);
}

// Propagation along the neighbour graph, not a global rule: on a torus the normals of the
// inner side point towards the centroid and must still agree with their neighbours.
TEST(PointCloudLaplacian, NormalsAreConsistentOnATorus) {
    const double major = 1.0, minor = 0.35;
    const int around = 120, across = 40;
    Points p(around * across, 3);
    Points expected(around * across, 3);
    for (int a = 0; a < around; ++a)
        for (int b = 0; b < across; ++b) {
            const double u = 2 * M_PI * (a + 0.5 * (b % 2)) / around, v = 2 * M_PI * b / across;
            const Eigen::RowVector3d n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
            p.row(a * across + b) = major * Eigen::RowVector3d(std::cos(u), std::sin(u), 0) + minor * n;
            expected.row(a * across + b) = n;
        }
    const PointCloudLaplacian cloud = point_cloud_laplacian(p);
    const Eigen::VectorXd agreement = cloud.normals.cwiseProduct(expected).rowwise().sum();
    EXPECT_GT(agreement.minCoeff(), 0.95);
    EXPECT_NEAR(cloud.laplacian.mass.sum() / (4 * M_PI * M_PI * major * minor), 1.0, 0.02);
}

// On a plane each interior point's fan is its star in the Delaunay triangulation of the whole
// cloud, so the soup is that triangulation three times over and K x = 0 for linear x inside.
TEST(PointCloudLaplacian, ReproducesLinearFunctionsInsideAPlanarCloud) {
    const int side = 30;
    Points p(side * side, 3);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    for (int i = 0; i < side; ++i)
        for (int j = 0; j < side; ++j) p.row(i * side + j) << i + jitter(rng), j + jitter(rng), 0.0;
    const PointCloudLaplacian cloud = point_cloud_laplacian(p);
    for (int axis = 0; axis < 2; ++axis) {
        const Eigen::VectorXd kx = cloud.laplacian.stiffness * p.col(axis);
        for (int i = 3; i < side - 3; ++i)
            for (int j = 3; j < side - 3; ++j) EXPECT_NEAR(kx[i * side + j], 0.0, 1e-9) << i << ", " << j;
    }
    for (Eigen::Index i = 0; i < p.rows(); ++i) EXPECT_NEAR(std::abs(cloud.normals(i, 2)), 1.0, 1e-12);
    // Boundary points' fans stop at the cloud's edge: nothing outside the convex hull. Along
    // the edge the fans disagree on the thin triangles between nearly collinear boundary
    // points (their circumcircles reach past some points' neighbourhoods), so the soup covers
    // a little less than the hull there (measured: 1.2 % of this cloud's area).
    const double hull = convex_hull_area(p);
    EXPECT_LT(cloud.laplacian.mass.sum(), hull);
    EXPECT_GT(cloud.laplacian.mass.sum(), 0.97 * hull);
}

// Two jittered sheets (the two sides of a thin part), 3 spacings apart: the other sheet's
// points are among an interior point's 30 nearest, and straight across they project next to
// it in its tangent plane, where a Delaunay fan over all 30 takes them. (The borders are left
// out: there the nearest 15 reach past the open side to the other sheet too. Measured, no
// interior fan crosses from a gap of 2.8 spacings up, against thousands with 30 candidates.)
TEST(PointCloudLaplacian, FansDoNotReachAcrossAThinSlab) {
    const int side = 24;
    const double gap = 3.0;
    Points p(2 * side * side, 3);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2);
    for (int sheet = 0; sheet < 2; ++sheet)
        for (int i = 0; i < side; ++i)
            for (int j = 0; j < side; ++j)
                p.row((sheet * side + i) * side + j) << i + jitter(rng), j + jitter(rng), sheet * gap + jitter(rng);
    const auto sheet_of = [&](Eigen::Index v) { return v >= side * side; };
    const auto interior = [&](Eigen::Index v) {
        const Eigen::Index i = (v % (side * side)) / side, j = v % side;
        return i >= 3 && j >= 3 && i < side - 3 && j < side - 3;
    };
    const auto across = [&](const PointCloudLaplacian& cloud) {
        long count = 0;
        for (Eigen::Index f = 0; f < cloud.local_triangles.rows(); ++f) {
            const Eigen::Index c = cloud.local_triangles(f, 0);
            count += interior(c) && (sheet_of(c) != sheet_of(cloud.local_triangles(f, 1)) ||
                                     sheet_of(c) != sheet_of(cloud.local_triangles(f, 2)));
        }
        return count;
    };
    PointCloudOptions all_candidates;
    all_candidates.fan_candidates = all_candidates.neighbours;
    EXPECT_EQ(across(point_cloud_laplacian(p)), 0);
    EXPECT_GT(across(point_cloud_laplacian(p, all_candidates)), 100);  // what the test would catch
}

// A dense scan line through a sparse grid: a line point's nearest 15 all lie on the line, so
// they make no triangle, and its fan comes from all 30 neighbours, which reach the grid.
TEST(PointCloudLaplacian, APointWhoseNearestLieOnALineTakesItsFanFromAllNeighbours) {
    const int side = 12;
    std::vector<Eigen::RowVector3d> rows;
    for (int i = 0; i < side; ++i)
        for (int j = 0; j < side; ++j) rows.emplace_back(i, j, 0.0);
    const int line_first = static_cast<int>(rows.size());
    for (int t = 0; t <= 60; ++t) rows.emplace_back(3.0 + 0.06 * t, 5.5, 0.0);  // spacing 0.06, between rows 5 and 6
    Points p(static_cast<Eigen::Index>(rows.size()), 3);
    for (size_t i = 0; i < rows.size(); ++i) p.row(static_cast<Eigen::Index>(i)) = rows[i];
    PointCloudLaplacian cloud;
    ASSERT_NO_THROW(cloud = point_cloud_laplacian(p));
    EXPECT_GT(cloud.fans_from_all_neighbours, 30);
    // Every line point is in a triangle with a grid point.
    std::vector<bool> reaches_grid(p.rows(), false);
    for (Eigen::Index f = 0; f < cloud.local_triangles.rows(); ++f)
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                if (cloud.local_triangles(f, b) < line_first) reaches_grid[cloud.local_triangles(f, a)] = true;
    for (Eigen::Index i = line_first; i < p.rows(); ++i) EXPECT_TRUE(reaches_grid[i]) << i;
}

TEST(PointCloudLaplacian, AStraightBorderOfALatticeAddsNoSliverAcrossItsOpenSide) {
    // A lattice of one scalene triangle, tilted and far from the origin, 1e-4 apart: what a
    // subdivided scan's points look like. A border point's two border neighbours lie straight
    // across it up to rounding, which alone would decide whether the open side gets a
    // triangle of no area and cotangents of 1e11.
    const int side = 40;
    const double spacing = 1e-4;
    const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ())).toRotationMatrix();
    Points p(side * side, 3);
    for (int i = 0; i < side; ++i)
        for (int j = 0; j < side; ++j) {
            const Eigen::Vector3d flat(spacing * (i + 0.37 * j), spacing * j, 0.0);
            p.row(i * side + j) = (tilt * flat + Eigen::Vector3d(0.61, -0.43, 0.87)).transpose();
        }
    const PointCloudLaplacian cloud = point_cloud_laplacian(p);
    std::vector<double> weights;
    for (Eigen::Index col = 0; col < cloud.laplacian.stiffness.outerSize(); ++col)
        for (SparseMatrix::InnerIterator it(cloud.laplacian.stiffness, col); it; ++it)
            if (it.row() != it.col()) weights.push_back(std::abs(it.value()));
    std::nth_element(weights.begin(), weights.begin() + weights.size() / 2, weights.end());
    const double median = weights[weights.size() / 2];
    // The lattice's own weights are cotangents of its angles (here 1.2 times the median at
    // most); a fan triangle within a degree of straight could add up to cot(1 deg) / 2 = 29.
    EXPECT_LT(*std::max_element(weights.begin(), weights.end()), 30 * median);
    const double hull = spacing * spacing * (side - 1) * (side - 1);  // the lattice's parallelogram
    EXPECT_NEAR(cloud.laplacian.mass.sum() / hull, 1.0, 0.03);
}

TEST(PointCloudLaplacian, NearestNeighboursMatchABruteForceSearch) {
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Points p(500, 3);
    for (Eigen::Index i = 0; i < p.size(); ++i) p.data()[i] = u(rng);
    const NeighbourTable table = nearest_neighbours(p, 10);
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
        std::vector<std::pair<double, int>> all;
        for (Eigen::Index j = 0; j < p.rows(); ++j)
            if (j != i) all.emplace_back((p.row(i) - p.row(j)).squaredNorm(), static_cast<int>(j));
        std::sort(all.begin(), all.end());
        for (int k = 0; k < 10; ++k) ASSERT_EQ(table(i, k), all[k].second) << "point " << i << ", neighbour " << k;
    }
}

TEST(PointCloudLaplacian, RefusesCloudsItCannotTriangulate) {
    EXPECT_NE(refusal(fibonacci_sphere(30, 1.0)).find("at least 31"), std::string::npos)
        << refusal(fibonacci_sphere(30, 1.0));
    EXPECT_EQ(refusal(fibonacci_sphere(30, 1.0), {20}), "") << "accepted";

    Points with_nan = fibonacci_sphere(100, 1.0);
    with_nan(42, 1) = NAN;
    EXPECT_NE(refusal(with_nan).find("point 42"), std::string::npos) << refusal(with_nan);
    EXPECT_NE(refusal(with_nan).find("non-finite"), std::string::npos);

    Points duplicated = fibonacci_sphere(100, 1.0);
    duplicated.row(7) = duplicated.row(70);
    duplicated.row(8) = duplicated.row(70);
    duplicated.row(9) = duplicated.row(90);
    EXPECT_NE(refusal(duplicated).find("3 exact duplicate"), std::string::npos) << refusal(duplicated);

    // A plane with a straight wire attached far away: the wire's points have collinear neighbours.
    Points wire(400 + 40, 3);
    for (int i = 0; i < 400; ++i) wire.row(i) << i % 20, i / 20, 0.0;
    for (int i = 0; i < 40; ++i) wire.row(400 + i) << 100.0 + 0.5 * i, 3.0, 1.0;
    EXPECT_NE(refusal(wire).find("lie on a line"), std::string::npos) << refusal(wire);

    EXPECT_NE(refusal(fibonacci_sphere(100, 1.0), {2}).find("at least 3 neighbours"), std::string::npos);
}
