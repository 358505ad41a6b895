// Scoring a smoother from the noisy surface alone, without the truth: Stein's unbiased risk
// estimate (Stein 1981) of its mean squared distance to the noise-free vertices, with the
// smoother's degrees of freedom measured by perturbing its input (Ye 1998's generalized
// degrees of freedom; the Monte-Carlo divergence of Ramani, Blu & Unser 2008) and the noise
// variance estimated on the mesh (noise_variance.h). Measuring the degrees of freedom covers
// smoothers whose operator is built from the noisy positions (cotangent weights), which are
// not linear in them; the trace of the linear filter alone overstated how well those do.
// Generalized cross-validation (Craven & Wahba 1979), which needs no variance, was used
// before: it divides the residual by (1 - dof/n)^2, which weighs the bias of a lowpass that
// passes half the noise 4x and misranked the candidates where they differ mostly in bias
// (the man in random directions: 16 % off the best; docs/results.md section 4).
#pragma once

#include "core/denoise/noise_direction.h"
#include "core/types.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace geofilter {

struct RiskEstimate {
    // Mean over the vertices on faces (those counted) of |y_i - F(y)_i|^2.
    double residual = 0;
    // How much of the noise F passes through: along the normals sum_i n_i . dF_i/dy_i n_i,
    // in every direction the trace of dF/dy.
    double degrees_of_freedom = 0;
    int vertices = 0;      // the vertices on faces (those with a normal)
    int observations = 0;  // noisy numbers: one per vertex along the normals, three in every direction
    // Stein's estimate of the mean over those vertices of |F(y)_i - x_i|^2, x the noise-free
    // positions: residual + (2 sum_i s_i^2 dof_i - sum_i s_i^2 obs_i) / vertices, s_i^2 the
    // variance of each of vertex i's noisy numbers, dof_i its share of the divergence.
    // Unbiased for noise that is Gaussian and independent from number to number; it may come
    // out slightly negative for a smoother that is nearly exact.
    double risk = 0;
    // The same estimate for leaving y as it is (residual 0, every noisy number passed): the
    // noise's own mean squared size, sum_i s_i^2 obs_i / vertices.
    double unchanged = 0;
};

using Smoother = std::function<Points(const Points&)>;
// A last step after the smoother that moves each vertex only along a direction it takes from
// the smoothed surface (Denoise's motion along the normals and volume offset: denoise.h).
using Finish = std::function<Points(const Points& y, const Points& smoothed)>;

// Estimates the risk of `smooth` at y under noise of `noise.model` (noise_direction.h) and variance
// `noise_variance[i]` per noisy number of vertex i (one per row of y). Along the normals, the degrees of freedom are the
// divergence of F along them, estimated with one random +-1 probe b as
// sum_i b_i n_i . (F(y + step b n) - F(y))_i / step (along one direction, the same with
// noise.direction for n_i); in every direction, the divergence of F in
// 3-D, with a random +-1 probe on each coordinate. Both unbiased; the relative spread is about
// sqrt(2 / dof). Which one matters for smoothers that keep the tangential positions
// (cotangent weights): along the normals they keep no noise there, in every direction they
// keep two thirds of it. `seed` fixes the probe, so that estimates for different smoothers
// with the same seed share it and compare more closely than their spread.
// With `finish`, the residual is that of finish(y, F(y)), the degrees of freedom still F's:
// with its directions held fixed, a step that keeps only the motion along the normals passes
// the noise along them exactly as F does. Probing the finished map itself was measured to
// overstate the risk of strong lowpasses (its guard against folds switches vertices between
// two positions): on bunny00 with noise of 0.5 mean edge lengths along the normals it chose a
// lowpass 1.8x farther from the truth. `smoothed` receives the (finished) result.
// `counted` (one flag per vertex, or empty for all): the vertices the means run over (the
// interior of patches cut out of a larger mesh: patches.h); the probe still moves them all.
// `smooth_perturbed`, when given, smooths the perturbed input instead of `smooth`, on another
// thread while `smooth` runs: the two runs are independent, and on a smoother that keeps its
// own state for each (Denoise's caches) the second core does the other half of the work.
RiskEstimate estimate_risk(const Points& y, const Triangles& triangles, const Smoother& smooth, double step,
                           std::uint64_t seed, const NoiseDirection& noise, const Eigen::VectorXd& noise_variance, Points* smoothed = nullptr,
                           const Finish& finish = {}, const std::vector<bool>& counted = {},
                           const Smoother& smooth_perturbed = {});

} // namespace geofilter
