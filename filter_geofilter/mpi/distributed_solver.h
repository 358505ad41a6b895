// The core's factored solver on PETSc matrices distributed over MPI ranks: the same
// algorithm (detail::apply_factored_transfer: real poles by a direct Cholesky solve, a complex
// pair by CG preconditioned with that factor, stopping on the core's error bound, or exactly
// by a complex LDL^T where the core's rule says so), with Kt = M^-1/2 K M^-1/2 partitioned by
// PETSc's MatPartitioning and factorised by MUMPS.
//
// Rank 0 runs the command line; the other ranks wait in serve_solves() until it calls
// solve_on_all_ranks() (from apply_filter, through FilterOptions::external_solver) or
// finish_serving().
#pragma once

#include "core/filter.h"

#include <mpi.h>

#include <string>
#include <vector>

namespace geofilter::mpi {

enum class PoleSolver {
    // MUMPS sparse Cholesky of Kt + c I (the core's factored solver, distributed).
    Direct,
    // For meshes whose factor does not fit: the pole solves by CG with an algebraic multigrid
    // preconditioner (hypre BoomerAMG) of Kt + c I, each to its share of the error budget.
    Multigrid,
};

struct EngineOptions {
    PoleSolver pole_solver = PoleSolver::Direct;
    // Rank 0 appends what the distributed solve measured (partition, factor size), for the log.
    std::vector<std::string>* log = nullptr;
};

// On rank 0: wakes the other ranks and solves `problem` with them (`options` reach them
// too). Throws Error as the core's solver would (the same messages); every rank sees the
// same failure.
Eigen::MatrixXd solve_on_all_ranks(MPI_Comm comm, FactoredProblem& problem, FilterReport& report,
                                   const EngineOptions& options);

// On every other rank: takes part in each solve rank 0 asks for; returns rank 0's exit status
// once it calls finish_serving().
int serve_solves(MPI_Comm comm);

// This process's peak resident memory so far (VmHWM), in bytes; 0 when unknown.
double peak_resident_bytes();

// On rank 0: releases the other ranks with the exit status of the run.
void finish_serving(MPI_Comm comm, int exit_status);

} // namespace geofilter::mpi
