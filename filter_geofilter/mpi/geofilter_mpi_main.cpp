// geofilter-mpi: `geofilter` under mpirun. Rank 0 runs geofilter's command line (the same
// presets, options, defaults, messages and files). A binary PLY filtered whole on the
// cotangent Laplacian is read, assembled and written by slices on every rank
// (distributed_pipeline.cpp); otherwise rank 0 reads and assembles the mesh, and the factored
// solve, where the time and memory go, runs on every rank (distributed_solver.cpp). Other ranks print nothing, so a
// refusal is one message, and every rank exits with rank 0's status.

#include "cli_run.h"
#include "distributed_pipeline.h"
#include "distributed_solver.h"

#include <petscsys.h>

#include <iostream>

namespace {

using namespace geofilter;

const char* const pole_solver_option = "--pole-solver";

// Takes geofilter-mpi's own option out of the arguments geofilter's parser sees.
mpi::EngineOptions take_engine_options(std::vector<std::string>& args) {
    mpi::EngineOptions engine;
    for (size_t i = 0; i < args.size(); ++i) {
        if (args[i] != pole_solver_option) continue;
        if (i + 1 >= args.size()) throw cli::UsageError(std::string(pole_solver_option) + " needs a value: direct or multigrid");
        const std::string value = args[i + 1];
        if (value == "direct")
            engine.pole_solver = mpi::PoleSolver::Direct;
        else if (value == "multigrid")
            engine.pole_solver = mpi::PoleSolver::Multigrid;
        else
            throw cli::UsageError(std::string(pole_solver_option) + " is direct or multigrid (got '" + value + "')");
        args.erase(args.begin() + long(i), args.begin() + long(i) + 2);
        --i;
    }
    return engine;
}

// What geofilter does that is not a filter of the whole mesh by the factored algorithm.
void refuse_undistributed(const cli::CliOptions& o) {
    const FilterSpec& spec = *o.preset;
    if (spec.parameter(param::region) && o.values.at(param::region) != 0)
        throw Error("--region: geofilter-mpi filters the whole mesh only (region filters are not distributed); use"
                    " geofilter for --region selected or quality");
    if (spec.parameter(param::solver) && o.values.at(param::solver) != 0)
        throw Error("--solver: geofilter-mpi runs the factored solver only (the paper's Jacobi-PCG is not"
                    " distributed); leave --solver at its default");
}

// After a successful run, one log line with every rank's peak memory (the benchmark reads it).
void report_peak_memory(MPI_Comm comm, bool print) {
    int ranks = 1, rank = 0;
    MPI_Comm_size(comm, &ranks);
    MPI_Comm_rank(comm, &rank);
    double mine = mpi::peak_resident_bytes();
    std::vector<double> all(static_cast<size_t>(ranks));
    MPI_Gather(&mine, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, comm);
    if (rank != 0 || !print) return;
    std::cerr << "geofilter-mpi: peak memory per rank (MiB):";
    for (double bytes : all) std::cerr << ' ' << format_number(bytes / (1024.0 * 1024.0), 4);
    std::cerr << std::endl;
}

bool has_flag(const std::vector<std::string>& args, const char* short_form, const char* long_form) {
    for (const auto& a : args)
        if (a == short_form || a == long_form) return true;
    return false;
}

} // namespace

int main(int argc, char** argv) {
    // PT-Scotch's parallel partitioner runs MPI collectives from several threads at once (its
    // folded halves partition concurrently): without thread support Open MPI deadlocks there
    // (seen at 4 ranks on the 1M-vertex torus read by slices).
    int threads = MPI_THREAD_SINGLE;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &threads);
    // PETSc's options come from PETSC_OPTIONS, never from the command line, which is geofilter's.
    PetscInitializeNoArguments();
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    MPI_Comm comm = PETSC_COMM_WORLD;
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    int status = 0;
    if (rank == 0) {
        std::vector<std::string> args(argv + 1, argv + argc);
        cli::CommandLineTool tool;
        tool.program = "geofilter-mpi";
        tool.check_options = refuse_undistributed;
        mpi::EngineOptions engine;
        std::vector<std::string> engine_log;
        try {
            engine = take_engine_options(args);
        } catch (const cli::UsageError& e) {
            std::cerr << tool.program << ": error: " << e.what() << std::endl;
            status = 2;
        }
        if (status == 0) {
            engine.log = &engine_log;
            tool.external_solver = [&](FactoredProblem& problem, FilterReport& report) {
                return mpi::solve_on_all_ranks(comm, problem, report, engine);
            };
            tool.filter_file = [&](const cli::CliOptions& o, const ParameterValues& values, const std::string& output,
                                   std::vector<std::string>& log) {
                return mpi::filter_file_on_all_ranks(comm, o, values, output, engine, log);
            };
            status = cli::run_command_line(args, tool);
            if (status == 0 && has_flag(args, "-h", "--help"))
                std::cout << "\ngeofilter-mpi runs the above under mpirun, and takes one more option:\n"
                             "  --pole-solver direct|multigrid  [direct]\n"
                             "      direct: MUMPS Cholesky factors (geofilter's factored solver, distributed);\n"
                             "      multigrid: CG with a hypre BoomerAMG preconditioner, no factor (the largest\n"
                             "      meshes). --region and --solver pcg are refused.\n";
        }
        mpi::finish_serving(comm, status);
        if (status == 0 && !has_flag(args, "-q", "--quiet"))
            for (const auto& line : engine_log) std::cerr << tool.program << ": " << line << '\n';
        if (status == 0) report_peak_memory(comm, !has_flag(args, "-q", "--quiet"));
    } else {
        status = mpi::serve_solves(comm);
        if (status == 0) report_peak_memory(comm, false);
    }
    PetscFinalize();
    MPI_Finalize();
    return status;
}
