#include "core/solve/shifted_cholesky.h"
#include "core/solve/solvers.h"

#include <new>

namespace geofilter::detail {

void ShiftedCholesky::analyse() {
    if (analysed_) return;
    use_amd_ordering(llt_.cholmod());
    llt_.analyzePattern(kt_);
    if (llt_.cholmod().status == CHOLMOD_OUT_OF_MEMORY) throw std::bad_alloc();
    analysed_ = true;
}

void ShiftedCholesky::factorize(double shift) {
    if (shift == shift_) return;
    analyse();
    shift_ = NAN;  // a failed factorisation leaves no usable factor behind
    llt_.setShift(shift);
    llt_.factorize(kt_);
    if (llt_.cholmod().status == CHOLMOD_OUT_OF_MEMORY) throw std::bad_alloc();
    if (llt_.info() != Eigen::Success)
        throw Error("the sparse Cholesky factorisation failed (Kt + " + format_number(shift) +
                    " I is not positive definite): the mesh has inverted or degenerate faces");
    shift_ = shift;
}

FactorState::FactorState(const Laplacian& laplacian)
    : sqrt_mass(laplacian.mass.cwiseSqrt()), kt(mass_normalized_stiffness(laplacian)),
      cholesky(kt) {}

} // namespace geofilter::detail
