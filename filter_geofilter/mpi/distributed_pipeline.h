// geofilter-mpi's whole pipeline without any rank holding the whole mesh: for a binary PLY of
// triangles and a filter of the whole mesh on the cotangent Laplacian, every rank reads its
// slice of the vertices and faces, checks them, measures its part of the selection, assembles
// its faces' part of K and M into distributed PETSc matrices, and writes its slice of the
// result. The connected components, the centroids, the bounding box and the feature's moments
// are reduced across ranks. Other files and options take the rank-0 path
// (distributed_solver.h), and the log says why.
#pragma once

#include "distributed_solver.h"

#include "cli/cli_options.h"
#include "run_filter.h"

#include <mpi.h>

#include <optional>
#include <string>
#include <vector>

namespace geofilter::mpi {

// On rank 0: filters o.input into `output` with every rank, or nothing (with the reason in
// `log`) when the file or the options need the whole mesh on rank 0. Throws Error as geofilter
// would; every rank fails alike.
std::optional<RunOutput> filter_file_on_all_ranks(MPI_Comm comm, const cli::CliOptions& o, const ParameterValues& values,
                                                  const std::string& output, const EngineOptions& engine,
                                                  std::vector<std::string>& log);

// On every other rank, woken by start_file_filter(): its part of that run.
void serve_file_filter(MPI_Comm comm);

} // namespace geofilter::mpi
