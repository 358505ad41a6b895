// Where the feature frequency comes from on the command line: a radius the user knows, or
// faces picked by a region (ball, box) or stored in the input file.
#pragma once

#include "cli_options.h"

#include <string>
#include <vector>

namespace geofilter::cli {

// Sets the frequency of a feature of radius `radius` as useSelection does with a measured
// one: s = 2/r^2 (sphere-like) or 1/r^2 (cylinder-like, by featureShape) becomes s1 with s2
// keeping its ratio s2/s1, or becomes the featureCorner of a pole-zero filter with the other
// corners keeping their ratios. Returns that frequency. Throws Error.
double apply_feature_radius(const FilterSpec& spec, ParameterValues& values, double radius, std::vector<std::string>& log);

// Faces whose three vertices lie inside any of the given regions, plus `stored` faces,
// in ascending order without repeats. Logs how many each source contributed.
std::vector<int> select_faces(const Points& points, const Triangles& triangles, const CliOptions& options,
                              const std::vector<int>& stored, std::vector<std::string>& log);

} // namespace geofilter::cli
