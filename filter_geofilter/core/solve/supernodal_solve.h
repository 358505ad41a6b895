// Solves with CHOLMOD's supernodal factor L L^T = P A P^T, all right-hand sides in one sweep
// over the factor. CHOLMOD's own solve hands each supernode to dense BLAS (trsm, gemm), which
// on the narrow blocks of a surface mesh (at 1M vertices ~8 columns by ~80 rows on average)
// and three right-hand sides runs well below what memory allows: on the 1M torus its
// three-column solve took 0.47-0.57 s, this sweep 0.40-0.42 s, a one-column solve 0.23 s
// (the factor's 630 MB read twice). The CG pair solves spend ~85 % of their time here.
// Internal to the core.
#pragma once

#include "core/types.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <cholmod.h>

namespace geofilter::detail {

// x <- (L L^T)^-1 x, x in the factor's order (rows permuted by P).
// `factor` is CHOLMOD's supernodal LL^T with int indices, numerically factorised.
void apply_supernodal_inverse(const cholmod_factor& factor, Eigen::MatrixXd& x);

// A^-1 b for b in the matrix's own order: P applied once before, P^T once after.
Eigen::MatrixXd solve_supernodal(const cholmod_factor& factor, const Eigen::MatrixXd& b);

// Eigen's wrapper, which analyses and factorises, with the factor it holds readable.
struct SupernodalCholesky : Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> {
    const cholmod_factor& factor() const { return *m_cholmodFactor; }
};

} // namespace geofilter::detail
