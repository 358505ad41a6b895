#include "spectral.h"

#include <gtest/gtest.h>

using namespace geofilter;

// docs/paper-notes.md §1: with the FEM factor 1/2, the coordinate functions of a sphere
// of radius r are eigenvectors of M^-1 K with eigenvalue 2/r^2 (eq. 17).
TEST(Laplace, SphereCoordinatesAreEigenvectorsWithEigenvalueTwoOverRSquared) {
    for (double r : {0.05, 1.0, 7.0}) {
        const Mesh sphere = icosphere(4, r);
        const Laplacian l = cotan_laplacian(sphere.points, sphere.triangles);
        for (int axis = 0; axis < 3; ++axis) {
            const Eigen::VectorXd x = sphere.points.col(axis);
            const Eigen::VectorXd kx = l.stiffness * x;
            const double rayleigh = x.dot(kx) / x.dot(l.mass.cwiseProduct(x));
            EXPECT_NEAR(rayleigh, 2 / (r * r), 0.01 * 2 / (r * r)) << "r = " << r << " axis " << axis;
            // Eigenvector, not just the right Rayleigh quotient: M^-1 K x is parallel to x.
            const Eigen::VectorXd lx = kx.cwiseQuotient(l.mass);
            EXPECT_LT((lx - rayleigh * x).norm(), 0.02 * rayleigh * x.norm());
        }
    }
}

TEST(Laplace, LowSphereSpectrumMatchesSphericalHarmonics) {
    // l(l+1)/r^2: 0 once, 2 three times, 6 five times (docs/paper-notes.md §1).
    const reference::Spectrum s = reference::spectrum_of(icosphere(3, 1.0));
    EXPECT_NEAR(s.eigenvalues[0], 0, 1e-9);
    for (int i = 1; i <= 3; ++i) EXPECT_NEAR(s.eigenvalues[i], 2, 0.01);
    for (int i = 4; i <= 8; ++i) EXPECT_NEAR(s.eigenvalues[i], 6, 0.06);
    EXPECT_GT(s.eigenvalues[9], 11);
}

TEST(Laplace, StiffnessIsSymmetricWithZeroRowSumsAndMassIsTheArea) {
    Mesh m = torus(24, 12, 1.0, 0.3);
    perturb_radially(m, 0.01, 7);
    const Laplacian l = cotan_laplacian(m.points, m.triangles);
    const Eigen::MatrixXd k(l.stiffness);
    EXPECT_LT((k - k.transpose()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((k * Eigen::VectorXd::Ones(k.cols())).cwiseAbs().maxCoeff(), 1e-10);
    double area = 0;
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
        const Eigen::Vector3d a = m.points.row(m.triangles(f, 0)), b = m.points.row(m.triangles(f, 1)),
                              c = m.points.row(m.triangles(f, 2));
        area += 0.5 * (b - a).cross(c - a).norm();
    }
    EXPECT_NEAR(l.mass.sum(), area, 1e-12 * area);
    // Positive semi-definite: no eigenvalue below rounding.
    const Eigen::VectorXd eigenvalues = reference::generalized_eigenvalues(k, Eigen::MatrixXd::Identity(k.rows(), k.cols()));
    EXPECT_GT(eigenvalues.minCoeff(), -1e-9);
}

TEST(Laplace, ObtuseTrianglesGiveNegativeWeightsButStayPositiveSemiDefinite) {
    // A flat fan with one very obtuse corner: the opposite edge's cotangent is negative.
    Mesh m;
    m.points.resize(4, 3);
    m.points << 0, 0, 0, 2, 0, 0, 1, 0.1, 0, 1, -1, 0;
    m.triangles.resize(2, 3);
    m.triangles << 0, 1, 2, 0, 3, 1;
    const Laplacian l = cotan_laplacian(m.points, m.triangles);
    EXPECT_GT(l.stiffness.coeff(0, 1), 0) << "edge 0-1 faces the obtuse corner: its weight must be negative";
    const Eigen::VectorXd eigenvalues = reference::generalized_eigenvalues(Eigen::MatrixXd(l.stiffness), Eigen::MatrixXd::Identity(4, 4));
    EXPECT_GT(eigenvalues.minCoeff(), -1e-9);
}
