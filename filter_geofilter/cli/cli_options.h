// The command line of `geofilter`: PRESET [options] INPUT OUTPUT. The filter parameters'
// options are generated from the filter table, so a parameter added there is accepted
// (and documented in --help) without code here.
#pragma once

#include "run_filter.h"

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace geofilter::cli {

// A mistake on the command line (exit status 2), as opposed to a refused run (1).
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct SphereRegion {
    Eigen::Vector3d center;
    double radius;
};
struct BoxRegion {
    Eigen::Vector3d low, high;
};

struct CliOptions {
    bool help = false;                 // print help (for `preset` when given) and exit
    const FilterSpec* preset = nullptr;
    ParameterValues values;            // every parameter of the preset; useSelection follows the regions
    std::string input, output;         // output may be empty for `measure`
    std::string plot;                  // --plot PNG, empty if not asked
    std::vector<SphereRegion> spheres; // --select-sphere (repeatable: the union is selected)
    std::vector<BoxRegion> boxes;      // --select-box
    bool select_stored = false;        // --select-stored
    bool quiet = false;
    bool overwrite_input = false;

    bool selects_region() const { return select_stored || !spheres.empty() || !boxes.empty(); }
};

// Throws UsageError with a one-line message.
CliOptions parse_command_line(const std::vector<std::string>& args);

// --help text: the overview, or everything about one preset.
std::string help_text(const FilterSpec* preset);

// The option that sets a table parameter: "maxIterations" -> "--max-iterations", "G0" -> "--G0".
std::string option_for(const std::string& parameter_name);

// The word a user types for an enum choice: the shortest unambiguous word of its label
// ("Sphere-like (s = 2/r^2)" -> "sphere", "Jacobi-PCG (paper)" -> "pcg").
std::vector<std::string> choice_keywords(const ParameterSpec& parameter);

} // namespace geofilter::cli
