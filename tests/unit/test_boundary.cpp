// fix_boundary: open boundaries stay put and the interior is filtered in the Dirichlet
// eigenbasis, relative to the harmonic extension of the boundary.
#include "core/mesh/boundary.h"
#include "core/filter/filter.h"
#include "core/design/butterworth.h"
#include "spectral.h"

#include <gtest/gtest.h>


using namespace geofilter;
using namespace geofilter::reference;

namespace {


// The Dirichlet split of a mesh, built here with dense matrices (no core routine but the
// Laplacian): K_II, K_IB, the interior masses and the harmonic extension from a dense
// factorisation of K_II.
struct DenseDirichlet {
    std::vector<Eigen::Index> interior, boundary;
    Eigen::MatrixXd k_ii, k_ib;
    Eigen::VectorXd m_i;
    Eigen::MatrixXd h;  // like p: p on the boundary, -K_II^-1 K_IB p_B inside
};

DenseDirichlet dense_dirichlet(const Laplacian& l, const std::vector<bool>& on_boundary, const Eigen::MatrixXd& p) {
    DenseDirichlet d;
    for (Eigen::Index i = 0; i < p.rows(); ++i) (on_boundary[i] ? d.boundary : d.interior).push_back(i);
    const Eigen::MatrixXd k = Eigen::MatrixXd(l.stiffness);
    const auto ni = Eigen::Index(d.interior.size()), nb = Eigen::Index(d.boundary.size());
    d.k_ii.resize(ni, ni);
    d.k_ib.resize(ni, nb);
    d.m_i.resize(ni);
    Eigen::MatrixXd p_b(nb, p.cols());
    for (Eigen::Index a = 0; a < ni; ++a) {
        d.m_i[a] = l.mass[d.interior[a]];
        for (Eigen::Index b = 0; b < ni; ++b) d.k_ii(a, b) = k(d.interior[a], d.interior[b]);
        for (Eigen::Index b = 0; b < nb; ++b) d.k_ib(a, b) = k(d.interior[a], d.boundary[b]);
    }
    for (Eigen::Index b = 0; b < nb; ++b) p_b.row(b) = p.row(d.boundary[b]);
    const Eigen::MatrixXd h_i = d.k_ii.ldlt().solve(-d.k_ib * p_b);
    d.h = p;
    for (Eigen::Index a = 0; a < ni; ++a) d.h.row(d.interior[a]) = h_i.row(a);
    return d;
}

} // namespace

TEST(Boundary, HarmonicExtensionIsHarmonicAndEqualsADenseSolve) {
    const Mesh g = wavy_sheet(24);
    const std::vector<bool> on_boundary = boundary_vertices(g.triangles, g.points.rows());
    const Laplacian l = cotan_laplacian(g.points, g.triangles);
    const Eigen::MatrixXd p = g.points;
    const Eigen::MatrixXd h = harmonic_extension(l, on_boundary, p);
    const DenseDirichlet d = dense_dirichlet(l, on_boundary, p);
    ASSERT_EQ(d.boundary.size(), 96u);

    // h = p on the boundary, exactly.
    for (Eigen::Index b : d.boundary) EXPECT_EQ(h.row(b), p.row(b)) << "boundary vertex " << b;
    // Harmonic inside: K_II h_I + K_IB p_B = 0, relative to |K| |p|.
    Eigen::MatrixXd h_i(d.interior.size(), 3), p_b(d.boundary.size(), 3);
    for (size_t a = 0; a < d.interior.size(); ++a) h_i.row(a) = h.row(d.interior[a]);
    for (size_t b = 0; b < d.boundary.size(); ++b) p_b.row(b) = p.row(d.boundary[b]);
    const double k_norm = Eigen::MatrixXd(l.stiffness).norm();
    EXPECT_LT((d.k_ii * h_i + d.k_ib * p_b).norm(), 1e-10 * k_norm * p.norm());
    // And the same as the dense solution.
    EXPECT_LT((h - d.h).cwiseAbs().maxCoeff(), 1e-10 * bbox_diagonal(g.points));
    // Not trivially so: the interior is not the input shape (the wave is not harmonic).
    EXPECT_GT((h - p).cwiseAbs().maxCoeff(), 1e-3);
}

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
    const Mesh g = wavy_sheet(24);
    const std::vector<bool> on_boundary = boundary_vertices(g.triangles, g.points.rows());
    const Laplacian l = cotan_laplacian(g.points, g.triangles);
    // The reference is dense throughout: the dense harmonic extension and the dense Dirichlet
    // eigenproblem K_II v = lambda M_I v, not the core's harmonic_extension/restrict_laplacian.
    const DenseDirichlet d = dense_dirichlet(l, on_boundary, g.points);
    const Eigen::MatrixXd& h = d.h;
    std::vector<bool> interior(on_boundary.size());
    for (size_t i = 0; i < interior.size(); ++i) interior[i] = !on_boundary[i];
    const reference::Spectrum eig = reference::dense_spectrum(d.k_ii, d.m_i);
    Eigen::MatrixXd detail(d.m_i.size(), 3);
    for (size_t i = 0, k = 0; i < interior.size(); ++i)
        if (interior[i]) detail.row(k++) = g.points.row(i) - h.row(i);

    for (const SecondOrderSpec& spec : {SecondOrderSpec{25, 50, 1, 1.1, 0}, SecondOrderSpec{100, 200, 1, 3, 0.9}}) {
        const TransferFunction tf = design_second_order(spec);
        Eigen::VectorXd gains(eig.eigenvalues.size());
        for (Eigen::Index i = 0; i < gains.size(); ++i) gains[i] = tf(eig.eigenvalues[i]);
        const Eigen::MatrixXd filtered_detail =
            eig.eigenvectors * (gains.asDiagonal() * (eig.eigenvectors.transpose() * (d.m_i.asDiagonal() * detail)));
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
    const Mesh g = wavy_sheet(24);
    const Points out = apply_filter(g.points, g.triangles, design_second_order({25, 50, 1, 1.1, 0}));
    EXPECT_GT((out.row(0) - g.points.row(0)).norm(), 1e-4);
}

TEST(Boundary, FieldWithFixedBoundaryEqualsExactDirichletSpectralFilterInEveryColumn) {
    // filter_field holds the boundary rows of a field of any width (Denoise's bump pattern
    // filters nine at once); each column is its own Dirichlet problem about its own harmonic
    // extension. The dense reference takes the columns one at a time.
    const Mesh g = wavy_sheet(20);
    const std::vector<bool> on_boundary = boundary_vertices(g.triangles, g.points.rows());
    const Laplacian l = cotan_laplacian(g.points, g.triangles);
    Eigen::MatrixXd field(g.points.rows(), 5);
    for (Eigen::Index i = 0; i < field.rows(); ++i) {
        const double x = g.points(i, 0), y = g.points(i, 1);
        field.row(i) << x, y * y, std::sin(7 * x) * std::cos(5 * y), 1.0, std::exp(-30 * (x * x + y * y));
    }
    const TransferFunction tf = design_butterworth_lowpass(200.0, 4);
    FilterOptions options;
    options.fix_boundary = true;
    for (Eigen::Index width : {Eigen::Index(1), Eigen::Index(5)}) {
        const Eigen::MatrixXd filtered = filter_field(g.points, g.triangles, tf, field.leftCols(width), options);
        for (Eigen::Index c = 0; c < width; ++c) {
            const DenseDirichlet d = dense_dirichlet(l, on_boundary, field.col(c));
            const reference::Spectrum eig = reference::dense_spectrum(d.k_ii, d.m_i);
            Eigen::VectorXd detail(d.m_i.size());
            for (size_t a = 0; a < d.interior.size(); ++a) detail[a] = field(d.interior[a], c) - d.h(d.interior[a], 0);
            Eigen::VectorXd gains(eig.eigenvalues.size());
            for (Eigen::Index i = 0; i < gains.size(); ++i) gains[i] = tf(eig.eigenvalues[i]);
            const Eigen::VectorXd kept =
                eig.eigenvectors * (gains.asDiagonal() * (eig.eigenvectors.transpose() * (d.m_i.asDiagonal() * detail)));
            double worst = 0;
            for (size_t a = 0; a < d.interior.size(); ++a)
                worst = std::max(worst, std::abs(filtered(d.interior[a], c) - d.h(d.interior[a], 0) - kept[a]));
            for (Eigen::Index b : d.boundary) EXPECT_EQ(filtered(b, c), field(b, c)) << "column " << c << ", boundary vertex " << b;
            EXPECT_LT(worst, 1e-5 * (field.col(c).cwiseAbs().maxCoeff() + 1)) << "column " << c << " of " << width;
            if (c == 2) EXPECT_GT((filtered.col(c) - field.col(c)).cwiseAbs().maxCoeff(), 1e-2) << "the wave must be smoothed";
        }
    }
}
