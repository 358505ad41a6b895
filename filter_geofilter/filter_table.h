// The one table of GeoFilter filters: names, parameters, defaults and help texts.
// Every adapter (MeshLab 2020.09, MeshLab 2022.02+, the command-line tool) reads it,
// so a name or a default is changed here and nowhere else.
#pragma once

#include "core/design/transfer_function.h"

#include <string>
#include <vector>

namespace geofilter {

enum class FilterKind { SecondOrder, PoleZero, Measure, Butterworth, Denoise };

// Length: a distance on the mesh. MeshLab shows it as an absolute value or a percentage of the
// bounding-box diagonal (RichAbsPerc); its table default is that fraction of the diagonal, so
// the default means the same on a mesh of any size.
enum class ParameterType { Float, Bool, Int, Enum, Length };

struct ParameterSpec {
    std::string name;   // as scripts spell it (e.g. "s1", "useSelection")
    ParameterType type;
    double default_value;          // bools as 0/1, enums as the index, lengths as a fraction of the diagonal
    std::string label;             // short, for dialogs
    std::string help;              // physical meaning, for tooltips and --help
    std::vector<std::string> choices;  // enum labels
    // The solver's settings and the paper's raw frequencies: MeshLab 2022+ folds these under
    // its dialog's advanced button; everywhere they come last.
    bool expert = false;
};

struct FilterSpec {
    std::string name;         // MeshLab filter name, e.g. "GeoFilter: Lowpass"
    std::string python_name;  // pymeshlab name, e.g. "apply_geofilter_lowpass"
    std::string cli_name;     // command-line preset, e.g. "lowpass"
    FilterKind kind;
    std::string description;  // filter help text (HTML allowed: MeshLab shows it as rich text)
    std::vector<ParameterSpec> parameters;
    // Second-order presets: the design the preset is named after (the paper's example). When the
    // frequency comes from a size (the radius, the selection), its ratio s2/s1 shapes the curve.
    SecondOrderSpec reference{};

    const ParameterSpec* parameter(const std::string& name) const;
};

const std::vector<FilterSpec>& filter_table();
const FilterSpec* find_filter(const std::string& name);  // by name, python name or cli name

// Names of the parameters every filtering entry shares.
namespace param {
inline const std::string radius = "radius";
inline const std::string s1 = "s1", s2 = "s2", G0 = "G0", G1 = "G1", Ginf = "Ginf";
inline const std::string use_selection = "useSelection", feature_shape = "featureShape";
inline const std::string feature_corner = "featureCorner";
inline const std::string fix_boundary = "fixBoundary";
inline const std::string solver = "solver", tolerance = "tolerance", max_iterations = "maxIterations";
inline const std::string region = "region", blend_width = "blendWidth";  // where the filter acts
inline const std::string zero_prefix = "z", pole_prefix = "p";  // z1..z4, p1..p4
inline const std::string cutoff = "cutoff", order = "order", laplace_operator = "operator";
constexpr int max_pole_zero = 4;
} // namespace param

} // namespace geofilter
