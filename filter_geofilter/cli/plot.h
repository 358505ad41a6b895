// --plot: the transfer function G(s) as a PNG, drawn by gnuplot.
#pragma once

#include "core/design/transfer_function.h"

#include <optional>
#include <string>
#include <vector>

namespace geofilter::cli {

struct PlotMarker {
    std::string label;  // e.g. "s1 = 25"
    double frequency;
};

struct TransferPlot {
    std::string title;
    TransferFunction g;
    std::vector<PlotMarker> markers;          // vertical lines; they also set the plotted range
    std::optional<PoleZeroSpec> asymptotes;   // pole-zero corners as used: draws their asymptotes
};

// |G(s)| on log-log axes, solid where G > 0 and dashed where G < 0. Throws Error when
// gnuplot is missing or fails. Writes exactly `png_path`.
void write_transfer_plot(const std::string& png_path, const TransferPlot& plot);

} // namespace geofilter::cli
