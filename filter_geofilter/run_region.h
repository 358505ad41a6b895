// The region parameters turned into a per-vertex weight and the weighted filter:
// run_filter's part for region != whole mesh, kept apart so that run_filter stays one path.
#pragma once

#include "core/filter/region.h"
#include "run_filter.h"

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace geofilter {

// The band's width when blendWidth is 0 (auto), and how it was chosen, for the log; asked
// only then. A width that is not > 0 refuses auto.
using AutoBlendWidth = std::function<std::pair<double, std::string>()>;

// The per-vertex weight in [0, 1] `region` asks for: region 1, 1 on the selected faces fading
// to 0 across a band of blendWidth (or auto_width's when it is 0); region 2, the vertex
// quality. Appends what it chose to `log`. Throws Error on a region it cannot use (no selected
// faces, no or NaN quality).
std::vector<double> region_weight_from_values(int region, double blend_width, const RunInput& input,
                                              const AutoBlendWidth& auto_width, std::vector<std::string>& log);

// Filters input with `g` where `values` put the region (region 1: the selected faces and a
// blend band of blendWidth, auto = the feature radius at s_feature for `shape`; region 2:
// the vertex quality as the weight). Appends what it did to `log`. Throws Error on a region
// it cannot use (no selected faces, no or NaN quality), before anything is changed.
Points filter_region(int region, double blend_width, const RunInput& input, const TransferFunction& g,
                     const FilterOptions& options, double s_feature, FeatureShape shape, FilterReport& report,
                     std::vector<std::string>& log);

} // namespace geofilter
