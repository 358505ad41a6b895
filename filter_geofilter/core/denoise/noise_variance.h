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
// by medians, as Donoho & Johnstone's estimator takes the finest band's median absolute
// value: where the clean mesh's own finest detail reaches the band (sharp edges, fingers,
// irregular sampling), those vertices' residuals are detail, and with the mean the estimate
// came 12-47 % above the noise added along the normals in 5 of the comparison's 22 cases
// (fandisk, the man at 0.1 h along the normals and at 0.3 h in random directions).
// The medians are local, one per vertex over its neighbourhood (noise_neighbourhood_vertices):
// a scanner's noise grows with depth and with the angle to the view, and one median over the
// whole mesh is that of the quiet part: on a scan whose noise along one view direction grew
// fivefold with depth it read a quarter of the mean variance, and every lowpass then scored
// worse than leaving the mesh as it was. Where the clean mesh's own detail fills most of a
// neighbourhood (a coarse CAD part's edges, at noise far below them) the median reads that
// detail: on a cube of 20 x 20 squares a side with noise of 0.001 edge lengths, 0.042 edge
// lengths (the lower quartile read 0.012, and was no better on the tuning half).
// Impulses: a vertex whose residual is farther than denoise_impulse_sigmas standard deviations
// of the residual its neighbourhood's noise leaves (Gaussian noise goes that far once in 5e8)
// is no sample of that noise but an outlier (a spike of a scan), when it also stands
// denoise_impulse_alone times farther out than any of its neighbours; or when it and its
// loudest neighbour are each other's loudest, both stand out, and each stands that much
// farther out than all its other neighbours: two outliers side by side hide each other from
// the first test, and no round of putting impulses back ever reveals either. On the tuning
// half of experiments/generalize_denoise's scans with outliers (1-2 % of the vertices) the
// pairs left 0.50-1.02e-3 RMS to the truth instead of 0.66-1.10; a nearly clean fandisk
// (noise 0.001 edge lengths) lost a few crease vertices to them: 0.030 -> 0.033 edge lengths.
// Looser pair rules took a diplodocus's tip or many of the fandisk's creases (docs/denoise.md).
#pragma once

#include "core/filter/filter.h"
#include "core/filter/filter_cache.h"
#include "core/denoise/noise_direction.h"
#include "core/types.h"

#include <optional>
#include <vector>

namespace geofilter {

// A vertex's noise is measured on the nearest vertices in rings around it, at least this
// many: the middle of that many squared residuals is within about 20 % of the variance (its
// standard error for a chi-square with one degree of freedom), and the risk estimate averages
// the per-vertex values over the mesh, so their spread averages out too. On the tuning half of
// experiments/generalize_denoise's noise families 32 and 64 end within 5 % of each other
// either way: geometric mean of Denoise's RMS over default Taubin's 0.671 with 32, 0.676 with
// 64; 32 closer on depth-dependent noise (the man: 21.0 against 21.9 degrees of normal error),
// 64 on scan debris (the man with holes: 11.2 against 14.9 degrees, 188 against 633 faces
// folded). 64 is kept for the smaller spread and the fewer folds.
constexpr int noise_neighbourhood_vertices = 64;
// A vertex whose neighbours all lie within this fraction of the diagonal of the plane through
// it along its normal reads no noise (a flat face of a clean CAD part): far below any noise
// that matters (a scan of 1M vertices has edges near 1e-3 of its diagonal), above the
// rounding of coordinates stored in single precision (6e-8 of their size).
constexpr double planar_ring_tolerance = 1e-6;
constexpr double denoise_impulse_sigmas = 6.0;
// Twice, not once: with "farther than every neighbour" the corners and edges of a nearly
// clean cube (noise 0.001 edge lengths) were taken for outliers round after round and worn
// away (580 vertices, 0.001 -> 0.089 edge lengths RMS); at twice, none were. The tuning half's
// scans with outliers paid for it: 0.66-1.11e-3 RMS against 0.23-0.80 (inputs 2.36-4.48).
constexpr double denoise_impulse_alone = 2.0;

struct NoiseVariance {
    Eigen::VectorXd per_vertex;  // s_i^2 of the noise along the normals (or the direction given) at each vertex (0 for a vertex in no face)
    double mean = 0;             // their mean over the vertices with a normal
    double degrees_of_freedom = 0;  // of the finest band's lowpass along the normals, per vertex
    double kept = 0;                // its squared action on the normal probe, per vertex
    std::vector<int> impulses;      // outliers (above), in increasing order
};

// The normals are smoothed_vertex_normals (noise_direction.h). `options` gives the solver and
// its tolerance (the operator is always the umbrella). Throws Error on a mesh without faces.
// The umbrella's two runs share `umbrella_cache` when given (else one of their own): the
// umbrella ignores the positions, so a caller's later umbrella runs on the same triangles
// (another round, the final lowpass) build nothing again. It should keep any size.
// With `along`, the noise is measured along that one direction at every vertex instead of
// along the normals (NoiseModel::AlongDirection).
NoiseVariance estimate_noise_variance(const Points& points, const Triangles& triangles, const FilterOptions& options,
                                      FilterCache* umbrella_cache = nullptr,
                                      const std::optional<Eigen::Vector3d>& along = std::nullopt);

// The noise estimate above reads the clean mesh's own finest detail too: an umbrella offset
// along the normal is the curvature times the local edge lengths squared, and on irregular
// sampling that varies from vertex to vertex like noise. On the five scans with no noise at
// all it read 0.008-0.06 mean edge lengths, and Denoise moved the clean man by 0.32e-3 RMS
// and folded 175 of its faces, the clean fandisk by 0.30e-3. That reading is taken again on
// the mesh smoothed along its normals by the umbrella lowpass at this per-vertex frequency
// (the middle of Denoise's umbrella cutoffs, where its search starts), its sampling kept: the
// noise is gone there, the curvature and the sampling are not; what it reads is subtracted,
// vertex by vertex. Four of the five clean scans then read no noise and are returned as they
// were (0.18 reads the same); on the tuning half, and on 35 more tuning draws (even seeds
// 12-20), one case of 56 chose another lowpass. Not for noise along one direction: keeping
// the sampling there keeps the noise's sideways part, which the smoothed mesh then reads as
// its own (the depth scans of the tuning half chose lowpasses 1.5-2.2x farther from the truth).
constexpr double own_detail_cutoff = 0.35;

// Subtracts from `variance`, estimated on `points`, what the same estimate reads on `points`
// smoothed along its normals by the umbrella lowpass of order `order` at own_detail_cutoff,
// vertex by vertex (never below zero); the means stay over the vertices the estimate counted.
// Returns the mean variance subtracted. Shares `umbrella_cache` as estimate_noise_variance does.
double subtract_own_detail(NoiseVariance& variance, const Points& points, const Triangles& triangles, int order,
                           const FilterOptions& options, FilterCache* umbrella_cache = nullptr);

} // namespace geofilter
