// Scoring a smoother from the noisy surface alone, without the truth: generalized
// cross-validation (Craven & Wahba 1979), with the smoother's degrees of freedom measured by
// perturbing its input (Ye 1998's generalized degrees of freedom; the Monte-Carlo divergence
// of Ramani, Blu & Unser 2008). Measuring them by perturbation covers smoothers whose operator
// is built from the noisy positions (cotangent weights), which are not linear in them; the
// trace of the linear filter alone overstated how well those smoothers do (notes in
// docs/results.md, section 4).
#pragma once

#include "noise_direction.h"
#include "types.h"

#include <cstdint>
#include <functional>

namespace geofilter {

struct CrossValidationScore {
    // Mean over the vertices on faces of |y_i - F(y)_i|^2.
    double residual = 0;
    // How much of the noise F passes through: along the normals sum_i n_i . dF_i/dy_i n_i,
    // in every direction the trace of dF/dy.
    double degrees_of_freedom = 0;
    int vertices = 0;      // the vertices on faces (those with a normal)
    int observations = 0;  // noisy numbers: one per vertex along the normals, three in every direction
    // residual / (1 - dof/observations)^2; +inf when F passes everything. Under noise that is
    // independent from vertex to vertex it estimates the mean squared distance of F(y) to the
    // noise-free surface, up to a constant that is the same for every smoother.
    double score = 0;
};

using Smoother = std::function<Points(const Points&)>;

// Scores `smooth` at y under noise of `model` (noise_direction.h). Along the normals, the
// degrees of freedom are the divergence of F along them, estimated with one random +-1
// probe b as sum_i b_i n_i . (F(y + step b n) - F(y))_i / step; in every direction, the
// divergence of F in 3-D, with a random +-1 probe on each coordinate. Both unbiased; the
// relative spread is about sqrt(2 / dof). Which one matters for smoothers that keep the
// tangential positions (cotangent weights): along the normals they keep no noise there, in
// every direction they keep two thirds of it. `seed` fixes the probe, so that scores of
// different smoothers with the same seed share it and compare more closely than their
// spread. `smoothed` receives F(y).
CrossValidationScore generalized_cross_validation(const Points& y, const Triangles& triangles, const Smoother& smooth,
                                                  double step, std::uint64_t seed, NoiseModel model,
                                                  Points* smoothed = nullptr);

} // namespace geofilter
