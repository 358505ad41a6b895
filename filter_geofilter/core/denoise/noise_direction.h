// Which way per-vertex noise moved the vertices, from the noisy mesh alone: only along the
// normals (a scanner's depth error), or in every direction (points jittered in 3-D, e.g. by
// registration or resampling). The Denoise filter's risk estimate needs to know: along the
// normals, a cotangent smoother that keeps the tangential positions keeps nothing noisy;
// jittered in 3-D, it keeps the tangential two thirds of the noise (docs/results.md section 4).
#pragma once

#include "core/types.h"

namespace geofilter {

enum class NoiseModel {
    AlongNormals,
    Isotropic,
    AlongDirection,  // along one direction everywhere (a scanner's depth error along its view)
};

const char* noise_model_name(NoiseModel model);

// The principal direction's share of the offsets' variance from which noise not along the
// normals is taken as along that one direction (estimate_noise_direction): twice the share of
// the two others together.
constexpr double noise_direction_share = 2.0 / 3.0;

// Where the noise is (estimate_noise_direction): vertices whose noise variance is at least
// this share of the mean. On a scan noisy in patches, the most regular part of the whole mesh
// lies where there is no noise, and there the ratio is the clean sampling's: bunny00 noisy
// along the normals on one half read 124.7 (noise in every direction), and the lowpass's
// sideways pull slid the clean half's vertices by 0.19 mean edge lengths; the elephant noisy
// in patches in random directions read 1.90 (along the normals) and kept its sideways noise.
// Chosen on the scan-patchy family's even draws (seeds 6-24) and on four scans noisy on one
// half: 0.25 and 0.35 read every draw the way it was noised. The window is narrow: at 0.1 the
// man noisy on one half reads in every direction again, at 0.5 that elephant along the
// normals again, at 1 also a fandisk noisy in patches in random directions (2.13 -> 3.99e-3
// RMS). A fixed share is a coarse line between "noisy" and "quiet"; docs/denoise.md says so.
constexpr double noisy_vertex_share = 0.35;

struct NoiseDirection {
    NoiseModel model = NoiseModel::AlongNormals;
    // In the most regular part of the mesh: the tangential part of the umbrella offsets
    // (mean of the neighbours minus the vertex) over their normal part, both squared.
    double tangential_ratio = 0;
    // The principal direction of the offsets (unit), and the share of their variance it holds:
    // 1/3 for noise in every direction, 1 for noise along one.
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();
    double direction_share = 0;
    // The tangential ratio again where the noise is (noisy_vertex_share), which then decides
    // (0: not read: no variance given, or the noise is along one direction).
    double tangential_ratio_where_noisy = 0;
};

// Noise that is independent from vertex to vertex and of variance s^2 along each axis it
// moves adds the same to each squared component of the umbrella offset (mean of the
// neighbours minus the vertex) and of that offset's own offset, which is what is split: the
// normal part then measures the noise along the normals, the tangential part (two axes)
// twice that when the noise is isotropic and nothing when it is along the normals. The clean
// mesh adds its own irregular sampling to the tangential part and its curvature to the
// normal part; taking the offset of the offsets cancels most of the curvature, which changes
// slowly along the surface, and the ratio is taken where the mesh is most regular: each part
// is averaged over a few rings of neighbours and the ratio is that of their 5 % quantiles over
// the mesh. Isotropic from a ratio of 2 (the pure-noise value) up. Measured on the
// comparison's five scans with Gaussian noise of 0.1-0.5 mean edge lengths: 0.005-1.72 along
// the normals (15 cases), 2.44-6.52 in random directions (7 cases); on the tuning half of
// experiments/generalize_denoise, 0.002-1.12 and 2.33-4.82, its tori sampled 3.6-4.5x longer
// one way and noised in random directions 2.51-2.59 (with the offsets themselves, 1.93-1.94:
// read as along the normals).
// Noise that is not along the normals may still be along one direction: a depth scanner's
// error lies along its view, whatever the surface's slant. Then the offsets' 3x3 covariance
// over the mesh has one large eigenvalue; noise in every direction spreads it evenly (each a
// third), and noise along the normals of a closed surface spreads it over the normals'
// directions. Along one direction from a principal share of noise_direction_share up.
// Noise that varies across the mesh (loud in patches, none between them) needs one more
// look: the most regular part of the whole mesh may be where there is no noise at all, and
// there the split is the clean sampling's, either way. Given the noise's per-vertex variance
// along the normals (`variance`, estimate_noise_variance), the ratio that tells along the
// normals from every direction is read again where the noise is (a variance of at least
// noisy_vertex_share of the mean), unless the whole mesh reads as noise along one direction:
// that noise's variance along the normals is largest where the view meets the surface head
// on, which reads it as along the normals.
NoiseDirection estimate_noise_direction(const Points& points, const Triangles& triangles,
                                        const Eigen::VectorXd* variance = nullptr);

// Unit vertex normals averaged over 3 rings of neighbours: the directions to split the
// noise along, without the noise's own tilt of each face (zero where a vertex has none).
Eigen::MatrixXd smoothed_vertex_normals(const Points& points, const Triangles& triangles);

} // namespace geofilter
