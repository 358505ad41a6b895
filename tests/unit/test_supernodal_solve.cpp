// The factored solver's own sweep over CHOLMOD's supernodal factor, against a dense Cholesky
// solve of the same matrix: any slip in the block layout, the permutation or the order of
// the sweeps shows as an error far above rounding.
#include "core/laplace.h"
#include "core/shifted_cholesky.h"
#include "core/solvers.h"
#include "core/supernodal_solve.h"
#include "shapes.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

using namespace geofilter;

namespace {

SparseMatrix perturbed_torus_kt() {
    Mesh m = torus(40, 30, 1.0, 0.4);
    perturb_radially(m, 0.01, 7);
    return mass_normalized_stiffness(cotan_laplacian(m.points, m.triangles));
}

double relative_error(const Eigen::MatrixXd& x, const Eigen::MatrixXd& reference) {
    return (x - reference).norm() / reference.norm();
}

} // namespace

TEST(SupernodalSolve, MatchesADenseCholeskySolveForAnyNumberOfColumns) {
    const SparseMatrix kt = perturbed_torus_kt();
    const double shift = 7.5;
    detail::ShiftedCholesky cholesky(kt);
    cholesky.factorize(shift);
    const Eigen::MatrixXd dense = Eigen::MatrixXd(kt) + shift * Eigen::MatrixXd::Identity(kt.rows(), kt.cols());
    const Eigen::LLT<Eigen::MatrixXd> reference(dense);
    for (int columns : {1, 3, 4}) {
        const Eigen::MatrixXd b = Eigen::MatrixXd::Random(kt.rows(), columns);
        const Eigen::MatrixXd once = reference.solve(b);
        EXPECT_LT(relative_error(cholesky.solve(b), once), 1e-11) << columns << " columns";
        EXPECT_LT(relative_error(cholesky.solve_squared(b), reference.solve(once)), 1e-11) << columns << " columns";
    }
}

// The test above proves something only if the factor has supernodes wider than one column
// (the dense triangle inside a block) and is permuted: checked on CHOLMOD's own factor of
// the same matrix, made with the same settings.
TEST(SupernodalSolve, HandlesWideSupernodesAndThePermutation) {
    const SparseMatrix kt = perturbed_torus_kt();
    Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt;
    detail::use_amd_ordering(llt.cholmod());
    llt.setShift(2.0);
    llt.compute(kt);
    ASSERT_EQ(llt.info(), Eigen::Success);
    cholmod_common common;
    cholmod_start(&common);
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_AMD;
    common.postorder = 1;
    common.supernodal = CHOLMOD_SUPERNODAL;
    cholmod_sparse a = Eigen::viewAsCholmod(kt);
    a.stype = -1;
    cholmod_factor* factor = cholmod_analyze(&a, &common);
    double beta[2] = {2.0, 0};
    cholmod_factorize_p(&a, beta, nullptr, 0, factor, &common);
    ASSERT_EQ(common.status, CHOLMOD_OK);
    const int* first_column = static_cast<const int*>(factor->super);
    int widest = 0;
    for (std::size_t s = 0; s < factor->nsuper; ++s) widest = std::max(widest, first_column[s + 1] - first_column[s]);
    EXPECT_GT(widest, 4);
    const int* perm = static_cast<const int*>(factor->Perm);
    int moved = 0;
    for (std::size_t k = 0; k < factor->n; ++k) moved += perm[k] != int(k);
    EXPECT_GT(moved, int(factor->n) / 2);
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(kt.rows(), 3);
    EXPECT_LT(relative_error(detail::solve_supernodal(*factor, b), llt.solve(b)), 1e-12);
    cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
}

TEST(SupernodalSolve, RefusesAFactorItCannotRead) {
    const SparseMatrix kt = perturbed_torus_kt();
    cholmod_common common;
    cholmod_start(&common);
    common.supernodal = CHOLMOD_SIMPLICIAL;
    cholmod_sparse a = Eigen::viewAsCholmod(kt);
    a.stype = -1;
    cholmod_factor* factor = cholmod_analyze(&a, &common);
    double beta[2] = {1.0, 0};
    cholmod_factorize_p(&a, beta, nullptr, 0, factor, &common);
    Eigen::MatrixXd x = Eigen::MatrixXd::Ones(kt.rows(), 3);
    EXPECT_THROW(detail::apply_supernodal_inverse(*factor, x, 1), std::logic_error);
    cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
}
