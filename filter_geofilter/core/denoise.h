// The rules of the Denoise filter: which Butterworth lowpass, on which operator, from what
// the user gives (a selected bump) or from the mesh alone. The constants were chosen by
// measurement (experiments/compare_denoise.py, docs/results.md), not tuned per mesh.
#pragma once

#include "butterworth.h"
#include "feature.h"
#include "operators.h"

#include <string>

namespace geofilter {

// A selected bump of radius r is one of a pattern to remove: cut at the frequency of
// features twice its size, so bumps of that size and smaller go while the flat passband
// keeps larger features and the volume. (Measured in docs/results.md section 4: the best
// cutoff radius lay at 1.5-2.5x the bump's; at 3-4x the filter eats features 5-8x larger.)
constexpr double denoise_radius_factor = 2.0;
constexpr int denoise_order = 4;

// Per-vertex sampling noise with nothing selected: the umbrella operator's per-vertex
// frequency (in [0, 2]) at which the lowpass cuts. Noise that is independent from vertex to
// vertex lives at the top of that range whatever the edge lengths, which a geometric
// (cotangent) cutoff cannot follow on an irregular mesh. Of the settings measured (umbrella
// 0.15-1, cotangent and intrinsic Delaunay at 0.75-2 mean edge lengths) only this one stayed
// within 10 % of MeshLab's default Taubin on every noise case.
constexpr double denoise_vertex_cutoff = 0.5;

struct DenoiseDesign {
    TransferFunction g;
    Operator op;
    double cutoff;       // in the operator's frequency units
    std::string origin;  // where the cutoff came from, for the log
};

// From a measured bump (sphere-like s = 2/R^2 or cylinder-like 1/R^2 with R = 2 r).
DenoiseDesign design_denoise_from_bump(const FeatureEllipsoid& bump, FeatureShape shape, int order, Operator op);
// From the mesh alone: the umbrella operator unless another is asked for (then the cutoff is
// that of features one mean edge length in radius).
DenoiseDesign design_denoise_from_sampling(double mean_edge_length, int order, Operator op);

} // namespace geofilter
