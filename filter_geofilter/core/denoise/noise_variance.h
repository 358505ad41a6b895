// How strong per-vertex noise is, from the noisy mesh alone: the variance s^2 that the risk
// estimate of the Denoise filter needs (risk_estimate.h). In the spirit of estimating image
// noise from the finest wavelet band (Donoho & Johnstone 1994), the finest band here is what
// the umbrella lowpass of order 4 cut at the per-vertex frequency 1 (the middle of its range
// [0, 2]) removes: the surface's own shape lies far below that frequency and passes, while
// about half of independent per-vertex noise goes. Only the part of that residual along the
// normals is used: the umbrella also pulls vertices sideways on irregular sampling, which is
// the clean mesh's, not noise. For a linear filter S and noise of variance s^2 along the
// normals n, the expected sum of squared normal residuals is s^2 (n - 2 dof + kept), with dof
// the divergence of S along the normals and kept the squared norm of its action on them, both
// measured with one random +-1 probe along the normals. On the comparison's five scans with
// Gaussian noise of 0.1-0.5 mean edge lengths (22 cases; docs/results.md section 4) it came
// within -6 % to +5 % of the variance of the noise added along the normals in 17 cases, and
// 12-47 % above it in 5 where the clean mesh's own finest detail competes with the noise
// (fandisk's sharp edges and the man's irregular sampling, at 0.1 h along the normals and at
// 0.3 h in random directions).
#pragma once

#include "core/filter/filter.h"
#include "core/denoise/noise_direction.h"
#include "core/types.h"

namespace geofilter {

struct NoiseVariance {
    double along_normals = 0;  // s^2: the variance of the noise along the normals
    double degrees_of_freedom = 0;  // of the finest band's lowpass along the normals, per vertex
    double kept = 0;                // its squared action on the normal probe, per vertex
};

// The normals are smoothed_vertex_normals (noise_direction.h). `options` gives the solver and
// its tolerance (the operator is always the umbrella). Throws Error on a mesh without faces.
NoiseVariance estimate_noise_variance(const Points& points, const Triangles& triangles, const FilterOptions& options);

} // namespace geofilter
