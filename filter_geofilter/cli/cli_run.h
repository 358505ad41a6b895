// One run of a GeoFilter command-line tool, from its arguments to its exit status: the
// whole of `geofilter`, and of `geofilter-mpi` on the rank that reads and writes the files.
#pragma once

#include "cli_options.h"
#include "run_filter.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace geofilter::cli {

struct CommandLineTool {
    std::string program = "geofilter";  // the prefix of every message
    // The factored solver's algorithm on another engine; empty: the core's.
    ExternalFactoredSolver external_solver;
    // Exact solves of complex pole pairs in the core's solver; empty: CG for every pair.
    ComplexShiftedFactorization complex_factorization;
    // Refuses (throws Error) options the tool cannot run, before any file is read.
    std::function<void(const CliOptions&)> check_options;
    // Filters INPUT into `output` (the temporary name the tool renames on success) without
    // this process reading the mesh whole (geofilter-mpi's reading by slices); `values` are
    // the parameters after --radius. Nothing, with the reason in `log`, when it does not take
    // these options or this file: the mesh is then read and filtered here.
    std::function<std::optional<RunOutput>(const CliOptions& options, const ParameterValues& values, const std::string& output,
                                           std::vector<std::string>& log)>
        filter_file;
};

// Parses `args` (without the program name), runs, prints the log, or one error line:
// exit status 0, 1 (refused) or 2 (bad command line). No output file unless it succeeded.
int run_command_line(const std::vector<std::string>& args, const CommandLineTool& tool);

} // namespace geofilter::cli
