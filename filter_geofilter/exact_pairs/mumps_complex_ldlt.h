// Complex pole pairs solved exactly: a complex-symmetric LDL^T of Kt - r I by sequential
// MUMPS (Debian: libmumps-seq-dev). A library of its own, not part of the core: sequential
// MUMPS ships a stand-in MPI whose MPI_Init and MPI_Comm_rank would clash with Open MPI in
// geofilter-mpi, which solves its pairs on its own distributed engine anyway.
#pragma once

#include "core/solve/complex_shifted_factor.h"

namespace geofilter {

// A ComplexShiftedFactorization: analyses `kt` (AMD ordering) and returns a factor holder,
// single precision first (mixed_precision_factor.h). `kt` must outlive it.
std::unique_ptr<ComplexShiftedFactor> mumps_complex_ldlt(const SparseMatrix& kt);

} // namespace geofilter
