// Complex pole pairs solved exactly on geofilter-mpi's ranks: a complex-symmetric LDL^T of
// Kt - r I by parallel MUMPS (Debian: libmumps-dev, the Open MPI build PETSc's MUMPS comes
// from; Debian's PETSc is real, so ZMUMPS is called directly). Kt is given as each rank's
// rows of a distributed PETSc matrix; the right-hand sides and solutions are each rank's rows.
#pragma once

#include "core/complex_shifted_factor.h"

#include <mpi.h>
#include <petscmat.h>

#include <memory>

namespace geofilter::mpi {

// Collective on `comm` (the communicator `kt` lives on). `kt` holds Kt + applied_shift I;
// the factor reads its entries once, here. Throws Error (on every rank) if MUMPS refuses it.
std::unique_ptr<ComplexShiftedFactor> distributed_complex_ldlt(MPI_Comm comm, Mat kt, double applied_shift);

} // namespace geofilter::mpi
