// Where the feature frequency comes from on the command line: a radius the user knows, or
// faces picked by a region (ball, box) or stored in the input file.
#pragma once

#include "cli_options.h"

#include <string>
#include <vector>

namespace geofilter::cli {

// Faces whose three vertices lie inside any of the given regions, plus `stored` faces,
// in ascending order without repeats. Logs how many each source contributed.
std::vector<int> select_faces(const Points& points, const Triangles& triangles, const CliOptions& options,
                              const std::vector<int>& stored, std::vector<std::string>& log);

// A point cloud's points inside any of the regions (--select-sphere, --select-box), in
// ascending order. Logs how many each region holds; refuses a region that holds none.
std::vector<int> select_points(const Points& points, const CliOptions& options, std::vector<std::string>& log);

} // namespace geofilter::cli
