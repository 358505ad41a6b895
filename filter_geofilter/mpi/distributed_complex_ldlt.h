// Complex pole pairs solved exactly on geofilter-mpi's ranks: a complex-symmetric LDL^T of
// Kt - r I by parallel MUMPS (Debian: libmumps-dev, the Open MPI build PETSc's MUMPS comes
// from; Debian's PETSc is real, so CMUMPS and ZMUMPS are called directly). Kt is given as each rank's
// rows of a distributed PETSc matrix; the right-hand sides and solutions are each rank's rows.
#pragma once

#include "core/solve/complex_shifted_factor.h"

#include <mpi.h>
#include <petscmat.h>

#include <memory>

namespace geofilter::mpi {

// Collective on `comm` (the communicator `kt` lives on). `kt` holds Kt + applied_shift I;
// the factor reads its entries here, in single precision (mixed_precision_factor.h), and
// again, with the shift then applied, if its precision must be raised: `kt` and
// `applied_shift` must outlive it. Throws Error (on every rank) if MUMPS refuses it.
std::unique_ptr<ComplexShiftedFactor> distributed_complex_ldlt(MPI_Comm comm, Mat kt, const double& applied_shift);

} // namespace geofilter::mpi
