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

#include "core/filter/filter.h"

#include <mpi.h>
#include <petscmat.h>

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

// Every scalar of a distributed solve, the same on every rank: the pole solver, the size, the
// error budget and iteration cap, and the transfer function.
struct DistributedProblem {
    PoleSolver pole_solver = PoleSolver::Direct;
    PetscInt vertices = 0;
    double allowed_error = 0;
    int max_iterations = 0;
    TransferFunction g;
};

// Throws Error naming `what` when a PETSc call failed (PETSc reports through return codes).
void check_petsc(PetscErrorCode code, const char* what);

// Collective: G(Kt) q, to the problem's error bound, for the rows of Kt (a matrix on `comm`,
// taken over and destroyed) and of q this rank holds. Adds to `report`; appends what MUMPS
// measured, in words, to `factor_note`.
Eigen::MatrixXd filter_rows(MPI_Comm comm, Mat& kt, const Eigen::MatrixXd& q, const DistributedProblem& problem,
                            FilterReport& report, std::string* factor_note);

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

// On rank 0: wakes the other ranks to filter a file with it (distributed_pipeline.h).
void start_file_filter(MPI_Comm comm);

// On rank 0: releases the other ranks with the exit status of the run.
void finish_serving(MPI_Comm comm, int exit_status);

} // namespace geofilter::mpi
