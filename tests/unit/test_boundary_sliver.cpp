// fixBoundary on a mesh with one sliver just above the degenerate-face threshold: the
// harmonic extension must stay harmonic (no regularising shift scaled by the stiffest
// vertex), and the filter must equal the dense Dirichlet spectral filter.
#include "core/mesh/boundary.h"
#include "core/filter/filter.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

using namespace geofilter;
using namespace geofilter::reference;

namespace {

// A wavy sheet in which one interior vertex is pulled almost onto the opposite edge of one
// of its triangles: that triangle's area is 1e-9 of its longest edge squared (the
// degenerate-face test skips faces below 1e-12), so its cotangents are ~1e9.
Mesh sheet_with_sliver() {
    Mesh g = wavy_sheet(16);
    const Eigen::Index face = 2 * (16 * 8 + 8);  // a triangle in the middle of the sheet
    const int v = g.triangles(face, 0), a = g.triangles(face, 1), b = g.triangles(face, 2);
    const Eigen::RowVector3d mid = 0.5 * (g.points.row(a) + g.points.row(b));
    g.points.row(v) = mid + 1e-9 * (g.points.row(v) - mid);
    return g;
}

} // namespace

TEST(BoundarySliver, HarmonicExtensionSolvesTheDirichletProblemExactly) {
    const Mesh g = sheet_with_sliver();
    const std::vector<bool> on_boundary = boundary_vertices(g.triangles, g.points.rows());
    const Laplacian l = cotan_laplacian(g.points, g.triangles);
    const Eigen::MatrixXd h = harmonic_extension(l, on_boundary, g.points);

    // Dense reference: K_II h_I = -K_IB p_B.
    std::vector<Eigen::Index> inner, rim;
    for (Eigen::Index i = 0; i < g.points.rows(); ++i) (on_boundary[i] ? rim : inner).push_back(i);
    const Eigen::MatrixXd k = Eigen::MatrixXd(l.stiffness);
    Eigen::MatrixXd k_ii(inner.size(), inner.size()), rhs = Eigen::MatrixXd::Zero(inner.size(), 3);
    for (size_t r = 0; r < inner.size(); ++r) {
        for (size_t c = 0; c < inner.size(); ++c) k_ii(r, c) = k(inner[r], inner[c]);
        for (Eigen::Index b : rim) rhs.row(r) -= k(inner[r], b) * g.points.row(b);
    }
    const Eigen::MatrixXd expected = k_ii.ldlt().solve(rhs);
    double worst = 0;
    for (size_t r = 0; r < inner.size(); ++r) worst = std::max(worst, (h.row(inner[r]) - expected.row(r)).norm());
    EXPECT_LT(worst, 1e-8);
}

TEST(BoundarySliver, FixedBoundaryFilterEqualsTheDenseDirichletFilter) {
    const Mesh g = sheet_with_sliver();
    const std::vector<bool> on_boundary = boundary_vertices(g.triangles, g.points.rows());
    std::vector<bool> interior(on_boundary.size());
    for (size_t i = 0; i < interior.size(); ++i) interior[i] = !on_boundary[i];
    const Laplacian l = cotan_laplacian(g.points, g.triangles);
    const Laplacian inner = restrict_laplacian(l, interior);

    // Reference: the boundary's dense harmonic extension plus the Dirichlet eigenbasis.
    std::vector<Eigen::Index> inner_index, rim;
    for (Eigen::Index i = 0; i < g.points.rows(); ++i) (on_boundary[i] ? rim : inner_index).push_back(i);
    const Eigen::MatrixXd k = Eigen::MatrixXd(l.stiffness);
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(inner_index.size(), 3);
    for (size_t r = 0; r < inner_index.size(); ++r)
        for (Eigen::Index b : rim) rhs.row(r) -= k(inner_index[r], b) * g.points.row(b);
    const Eigen::MatrixXd k_ii = Eigen::MatrixXd(inner.stiffness);
    const Eigen::MatrixXd h = k_ii.ldlt().solve(rhs);
    Eigen::MatrixXd detail(inner_index.size(), 3);
    for (size_t r = 0; r < inner_index.size(); ++r) detail.row(r) = g.points.row(inner_index[r]) - h.row(r);
    const reference::Spectrum eig = reference::dense_spectrum(k_ii, inner.mass);

    // G0 = 0: the smooth part of the detail is removed, so a wrong h shows in full.
    const TransferFunction tf = design_second_order({25, 100, 0, 2, 0});
    Eigen::VectorXd gains(eig.eigenvalues.size());
    for (Eigen::Index i = 0; i < gains.size(); ++i) gains[i] = tf(eig.eigenvalues[i]);
    const Eigen::MatrixXd expected =
        h + eig.eigenvectors * (gains.asDiagonal() * (eig.eigenvectors.transpose() * (inner.mass.asDiagonal() * detail)));

    FilterOptions options;
    options.fix_boundary = true;
    const Points out = apply_filter(g.points, g.triangles, tf, options);
    double worst = 0;
    for (size_t r = 0; r < inner_index.size(); ++r) worst = std::max(worst, (out.row(inner_index[r]) - expected.row(r)).norm());
    EXPECT_LT(worst, 1e-6 * bbox_diagonal(g.points));
}
