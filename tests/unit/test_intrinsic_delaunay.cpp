// The intrinsic Delaunay operator: non-negative weights where the plain cotangent has
// negative ones, the same Laplace-Beltrami limit, the same area, and nothing changed on a
// mesh that is already Delaunay.
#include "core/operators/intrinsic_delaunay.h"
#include "core/operators/operators.h"
#include "shapes.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <set>

#include <Eigen/SparseCholesky>

#include <random>

using namespace geofilter;

namespace {

// Moves every vertex along the sphere by up to `amount` edge lengths, then back onto it:
// an irregular sampling of the same surface, with obtuse triangles.
Mesh jittered_sphere(int levels, double radius, double amount, unsigned seed) {
    Mesh m = icosphere(levels, radius);
    const double h = radius * 1.1 / (1 << levels);  // about the mean edge length
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0, amount * h);
    for (Eigen::Index i = 0; i < m.points.rows(); ++i) {
        Eigen::RowVector3d p = m.points.row(i) + Eigen::RowVector3d(n(rng), n(rng), n(rng));
        m.points.row(i) = radius * p.normalized();
    }
    return m;
}

double max_off_diagonal(const SparseMatrix& k) {
    double worst = -INFINITY;
    for (Eigen::Index col = 0; col < k.outerSize(); ++col)
        for (SparseMatrix::InnerIterator it(k, col); it; ++it)
            if (it.row() != col) worst = std::max(worst, it.value());
    return worst;
}

// The three eigenvalues of K v = s M v next above 0, by subspace inverse iteration from the
// coordinate functions (a sphere's first non-constant eigenspace), then Rayleigh-Ritz.
Eigen::Vector3d lowest_nonzero_eigenvalues(const Laplacian& l, const Points& points) {
    const SparseMatrix m = SparseMatrix(l.mass.asDiagonal());
    const double shift = 1e-3 * l.mass.sum() / l.stiffness.diagonal().sum();  // keeps K + shift M definite
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(SparseMatrix(l.stiffness + shift * m));
    Eigen::MatrixXd x = points;
    for (int it = 0; it < 30; ++it) {
        x = x.rowwise() - (l.mass.transpose() * x) / l.mass.sum();  // off the constant mode
        x = ldlt.solve(m * x);
        const Eigen::MatrixXd g = x.transpose() * m * x;
        x = x * Eigen::MatrixXd(g.llt().matrixL()).transpose().inverse();  // M-orthonormal
    }
    return reference::generalized_eigenvalues(x.transpose() * l.stiffness * x, x.transpose() * m * x);
}

} // namespace

TEST(IntrinsicDelaunay, WeightsAreNonNegativeOnANoisyIrregularMesh) {
    Mesh m = jittered_sphere(3, 1.0, 0.35, 4);
    perturb_radially(m, 0.03, 9);
    // The test means something only if the plain cotangent operator has negative weights here.
    ASSERT_GT(max_off_diagonal(cotan_laplacian(m.points, m.triangles).stiffness), 1e-3);
    IntrinsicDelaunayStats stats;
    const Laplacian l = intrinsic_delaunay_laplacian(m.points, m.triangles, &stats);
    EXPECT_GT(stats.flips, 0);
    EXPECT_EQ(stats.non_delaunay_edges_left, 0);
    EXPECT_LE(max_off_diagonal(l.stiffness), 1e-9);
    // Rows still sum to zero (constants are in the kernel).
    const Eigen::VectorXd rows = l.stiffness * Eigen::VectorXd::Ones(m.points.rows());
    EXPECT_LT(rows.cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_NEAR(l.mass.sum(), cotan_laplacian(m.points, m.triangles).mass.sum(), 1e-12 * l.mass.sum());
}

TEST(IntrinsicDelaunay, SphereEigenvalueTwoOverRSquaredWithinOnePercent) {
    for (double r : {0.5, 2.0}) {
        const Mesh m = jittered_sphere(4, r, 0.25, 7);
        IntrinsicDelaunayStats stats;
        const Laplacian l = intrinsic_delaunay_laplacian(m.points, m.triangles, &stats);
        ASSERT_GT(stats.flips, 100);  // the sampling is irregular enough to matter
        const Eigen::Vector3d lambda = lowest_nonzero_eigenvalues(l, m.points);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(lambda[k] * r * r / 2, 1.0, 0.01) << "r = " << r;
    }
}

TEST(IntrinsicDelaunay, AlreadyDelaunayMeshKeepsThePlainCotangentOperator) {
    for (const Mesh& m : {icosphere(3, 1.3), torus(30, 20, 1.0, 0.4)}) {
        IntrinsicDelaunayStats stats;
        const Laplacian l = intrinsic_delaunay_laplacian(m.points, m.triangles, &stats);
        const Laplacian plain = cotan_laplacian(m.points, m.triangles);
        EXPECT_EQ(stats.flips, 0);
        EXPECT_LT((Eigen::MatrixXd(l.stiffness) - Eigen::MatrixXd(plain.stiffness)).cwiseAbs().maxCoeff(), 1e-10);
        EXPECT_LT((l.mass - plain.mass).cwiseAbs().maxCoeff(), 1e-12);
    }
}

TEST(IntrinsicDelaunay, BoundaryEdgesAreNeverFlipped) {
    // A flat grid with one long thin strip: boundary rows keep their edges, area unchanged.
    Mesh m = grid(12, 1.0);
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(-0.015, 0.015);  // < a quarter of the spacing: no inverted triangle
    for (Eigen::Index i = 0; i < m.points.rows(); ++i) {
        const double x = m.points(i, 0), y = m.points(i, 1);
        if (std::abs(std::abs(x) - 0.5) > 1e-9 && std::abs(std::abs(y) - 0.5) > 1e-9) {
            m.points(i, 0) += u(rng);
            m.points(i, 1) += u(rng);
        }
    }
    IntrinsicDelaunayStats stats;
    const Laplacian l = intrinsic_delaunay_laplacian(m.points, m.triangles, &stats);
    EXPECT_NEAR(l.mass.sum(), 1.0, 1e-12);
    EXPECT_GT(stats.flips, 10);
    const Laplacian plain = cotan_laplacian(m.points, m.triangles);
    // A planar Delaunay Laplacian still reproduces linear functions exactly (K x = 0 inside).
    const Eigen::VectorXd kx = l.stiffness * m.points.col(0);
    for (Eigen::Index i = 0; i < m.points.rows(); ++i)
        if (std::abs(std::abs(m.points(i, 0)) - 0.5) > 1e-9 && std::abs(std::abs(m.points(i, 1)) - 0.5) > 1e-9)
            EXPECT_NEAR(kx[i], 0.0, 1e-10);
    EXPECT_NEAR((l.stiffness * m.points.col(0)).sum(), (plain.stiffness * m.points.col(0)).sum(), 1e-10);
}

TEST(UmbrellaOperator, GraphLaplacianWithDegreeMass) {
    const Mesh m = icosphere(2, 1.0);
    const Laplacian l = umbrella_laplacian(m.triangles, m.points.rows());
    for (Eigen::Index i = 0; i < m.points.rows(); ++i) {
        EXPECT_EQ(l.stiffness.coeff(i, i), l.mass[i]);
        EXPECT_TRUE(l.mass[i] == 5 || l.mass[i] == 6);
    }
    EXPECT_LT((l.stiffness * Eigen::VectorXd::Ones(m.points.rows())).cwiseAbs().maxCoeff(), 1e-12);
}

// Entry by entry against the edge set listed from the faces: -1 on each edge, the degree on
// the diagonal and as the mass; a vertex in no face has no entry at all (nothing names it),
// and a face with a repeated corner adds its one true edge, none from a vertex to itself.
TEST(UmbrellaOperator, EveryEntryIsTheEdgeSetOfTheFaces) {
    Mesh m = icosphere(2, 1.0);
    const Eigen::Index isolated = m.points.rows();
    m.points.conservativeResize(m.points.rows() + 1, 3);
    m.points.row(isolated) << 3, 0, 0;
    m.triangles.conservativeResize(m.triangles.rows() + 1, 3);
    m.triangles.row(m.triangles.rows() - 1) << 0, 0, 7;
    const Eigen::Index n = m.points.rows();
    std::set<std::pair<int, int>> edges;
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
        for (int k = 0; k < 3; ++k) {
            const int a = m.triangles(f, k), b = m.triangles(f, (k + 1) % 3);
            if (a != b) edges.insert({std::min(a, b), std::max(a, b)});
        }
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(n, n);
    for (const auto& [a, b] : edges) {
        expected(a, b) = expected(b, a) = -1;
        expected(a, a) += 1;
        expected(b, b) += 1;
    }
    const Laplacian l = umbrella_laplacian(m.triangles, n);
    EXPECT_EQ((Eigen::MatrixXd(l.stiffness) - expected).cwiseAbs().maxCoeff(), 0.0);
    for (Eigen::Index i = 0; i < n; ++i) EXPECT_EQ(l.mass[i], expected(i, i)) << i;
    EXPECT_EQ(l.stiffness.col(isolated).nonZeros(), 0);
}
