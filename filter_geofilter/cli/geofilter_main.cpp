// geofilter: the GeoFilter filters on the command line (cli_run.cpp does the work).
#include "cli_run.h"
#include "exact_pairs.h"

int main(int argc, char** argv) {
    geofilter::cli::CommandLineTool tool;
    tool.complex_factorization = geofilter::exact_pair_factorization();
    return geofilter::cli::run_command_line(std::vector<std::string>(argv + 1, argv + argc), tool);
}
