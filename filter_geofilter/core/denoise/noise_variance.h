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
// measured with one random +-1 probe along the normals. The squared residuals are summarised
// by their median, as Donoho & Johnstone's estimator takes the finest band's median absolute
// value: where the clean mesh's own finest detail reaches the band (sharp edges, fingers,
// irregular sampling), those vertices' residuals are detail, and with the mean the estimate
// came 12-47 % above the noise added along the normals in 5 of the comparison's 22 cases
// (fandisk, the man at 0.1 h along the normals and at 0.3 h in random directions). With the
// median, on 30 noisy scans (five meshes, 0.1-0.5 h, both directions) Denoise ended as close
// to the truth or closer: the man at 0.1 h along the normals 0.472 -> 0.428e-3 RMS, the
// diplodocus at 0.1 h in random directions 0.324 -> 0.314e-3, the rest within 0.2 %.
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
