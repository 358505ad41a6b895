// fix_boundary: open boundaries stay put and the interior is filtered in the Dirichlet
// eigenbasis, relative to the harmonic extension of the boundary.
#include "core/boundary.h"
#include "core/filter.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

using namespace geofilter;
using namespace geofilter::reference;

namespace {

Mesh wavy_sheet() {
    Mesh g = grid(24, 1.0);
    for (Eigen::Index i = 0; i < g.points.rows(); ++i) {
        const double x = g.points(i, 0), y = g.points(i, 1);
        g.points(i, 2) = 0.05 * std::sin(9 * x) * std::cos(7 * y) + 0.1 * x * y;
    }
    return g;
}

} // namespace

TEST(Boundary, FindsTheRimOfAGrid) {
    const Mesh g = grid(4, 1.0);
    const std::vector<bool> b = boundary_vertices(g.triangles, g.points.rows());
    EXPECT_EQ(std::count(b.begin(), b.end(), true), 16);
    EXPECT_FALSE(b[6]);  // (1, 1) is inside
    const Mesh s = icosphere(2);
    const std::vector<bool> none = boundary_vertices(s.triangles, s.points.rows());
    EXPECT_EQ(std::count(none.begin(), none.end(), true), 0);
}

TEST(Boundary, FixedBoundaryEqualsExactDirichletSpectralFilter) {
    const Mesh g = wavy_sheet();
    const std::vector<bool> on_boundary = boundary_vertices(g.triangles, g.points.rows());
    const Laplacian l = cotan_laplacian(g.points, g.triangles);
    const Eigen::MatrixXd h = harmonic_extension(l, on_boundary, g.points);

    std::vector<bool> interior(on_boundary.size());
    for (size_t i = 0; i < interior.size(); ++i) interior[i] = !on_boundary[i];
    const Laplacian inner = restrict_laplacian(l, interior);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(inner.stiffness),
                                                                   Eigen::MatrixXd(inner.mass.asDiagonal()));
    Eigen::MatrixXd detail(inner.mass.size(), 3);
    for (size_t i = 0, k = 0; i < interior.size(); ++i)
        if (interior[i]) detail.row(k++) = g.points.row(i) - h.row(i);

    for (const SecondOrderSpec& spec : {SecondOrderSpec{25, 50, 1, 1.1, 0}, SecondOrderSpec{100, 200, 1, 3, 0.9}}) {
        const TransferFunction tf = design_second_order(spec);
        Eigen::VectorXd gains(eig.eigenvalues().size());
        for (Eigen::Index i = 0; i < gains.size(); ++i) gains[i] = tf(eig.eigenvalues()[i]);
        const Eigen::MatrixXd filtered_detail =
            eig.eigenvectors() * (gains.asDiagonal() * (eig.eigenvectors().transpose() * (inner.mass.asDiagonal() * detail)));
        for (Solver solver : {Solver::Factored, Solver::JacobiPcg}) {
            FilterOptions options;
            options.fix_boundary = true;
            options.solver = solver;
            FilterReport report;
            const Points out = apply_filter(g.points, g.triangles, tf, options, &report);
            EXPECT_EQ(report.fixed_vertices, 96);
            double worst = 0;
            for (size_t i = 0, k = 0; i < interior.size(); ++i) {
                if (interior[i])
                    worst = std::max(worst, (out.row(i) - h.row(i) - filtered_detail.row(k++)).norm());
                else
                    EXPECT_EQ(out.row(i), g.points.row(i)) << "boundary vertex " << i << " moved";
            }
            EXPECT_LT(worst, 1e-6 * bbox_diagonal(g.points)) << solver_name(solver);
            EXPECT_GT((out - g.points).rowwise().norm().maxCoeff(), 1e-3) << "the interior must change";
        }
    }
}

TEST(Boundary, ClosedMeshIsFilteredAsWithoutTheOptionAndSaysSo) {
    const Mesh s = icosphere(3, 0.5);
    const TransferFunction tf = design_second_order({10, 25, 1, 30, 0});
    FilterOptions fixed;
    fixed.fix_boundary = true;
    FilterReport report;
    const Points a = apply_filter(s.points, s.triangles, tf, fixed, &report);
    const Points b = apply_filter(s.points, s.triangles, tf);
    EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-12);
    ASSERT_EQ(report.warnings.size(), 1u);
    EXPECT_NE(report.warnings[0].find("no open boundary"), std::string::npos);
}

TEST(Boundary, FreeBoundaryMovesTheRim) {
    // The default: the paper's natural boundary lets the rim move (a lowpass pulls it in).
    const Mesh g = wavy_sheet();
    const Points out = apply_filter(g.points, g.triangles, design_second_order({25, 50, 1, 1.1, 0}));
    EXPECT_GT((out.row(0) - g.points.row(0)).norm(), 1e-4);
}
