// The factored solver's own sweep over CHOLMOD's supernodal factor, against a dense Cholesky
// solve of the same matrix: any slip in the block layout, the permutation or the order of
// the sweeps shows as an error far above rounding.
#include "core/operators/laplace.h"
#include "core/solve/shifted_cholesky.h"
#include "core/solve/solvers.h"
#include "core/solve/supernodal_solve.h"
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

// CHOLMOD's own factor of Kt + shift I, AMD-ordered and postordered like the solver's,
// supernodal or simplicial as asked.
struct CholmodFactor {
    cholmod_common common;
    cholmod_factor* factor = nullptr;
    int status = CHOLMOD_OK;

    CholmodFactor(const SparseMatrix& kt, double shift, int supernodal) {
        cholmod_start(&common);
        common.nmethods = 1;
        common.method[0].ordering = CHOLMOD_AMD;
        common.postorder = 1;
        common.supernodal = supernodal;
        cholmod_sparse a = Eigen::viewAsCholmod(const_cast<SparseMatrix&>(kt));
        a.stype = -1;
        factor = cholmod_analyze(&a, &common);
        double beta[2] = {shift, 0};
        cholmod_factorize_p(&a, beta, nullptr, 0, factor, &common);
        status = common.status;
    }
    CholmodFactor(const CholmodFactor&) = delete;
    CholmodFactor& operator=(const CholmodFactor&) = delete;
    ~CholmodFactor() {
        cholmod_free_factor(&factor, &common);
        cholmod_finish(&common);
    }
};

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
    const CholmodFactor own(kt, 2.0, CHOLMOD_SUPERNODAL);
    ASSERT_EQ(own.status, CHOLMOD_OK);
    const cholmod_factor* factor = own.factor;
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
}

TEST(SupernodalSolve, RefusesAFactorItCannotRead) {
    const SparseMatrix kt = perturbed_torus_kt();
    const CholmodFactor simplicial(kt, 1.0, CHOLMOD_SIMPLICIAL);
    ASSERT_EQ(simplicial.status, CHOLMOD_OK);
    Eigen::MatrixXd x = Eigen::MatrixXd::Ones(kt.rows(), 3);
    EXPECT_THROW(detail::apply_supernodal_inverse(*simplicial.factor, x), std::logic_error);
}
