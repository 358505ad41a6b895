// geofilter: the GeoFilter filters on the command line (cli_run.cpp does the work).
#include "cli_run.h"

int main(int argc, char** argv) {
    return geofilter::cli::run_command_line(std::vector<std::string>(argv + 1, argv + argc), {});
}
