// Removing a pattern of bumps like the one the user selected. A flat lowpass cut below the
// bumps' size removes what varies between them, but keeps the pattern's local mean height,
// a low-frequency offset: on a sphere covered with Gaussian bumps the lowpassed surface lies
// above the bare sphere by up to 2.6 % in volume (docs/results.md section 4), and where the
// bumps crowd, their tails never let the surface show the base between them. What the
// lowpass removed, d = (input - lowpass) . n, is the pattern minus what the lowpass kept of it:
// d = H - LP(H). The selection says what one bump looks like, so the pattern is modelled as
// H = sum_i a_i phi(|x - x_i|): centres x_i where d peaks, heights a_i >= 0, one profile phi.
// What the lowpass removes of one such bump, psi = phi - LP(phi), is computed by the same
// lowpass on a patch around the selected bump, and sum_i a_i psi(|x - x_i|) (plus one offset)
// is fitted to d by least squares. phi starts as the Gaussian exp(-r^2 / w^2) whose width
// best explains the selected bump and its nearest peaks; its shape is then learned from them
// (piecewise linear, falling outwards), since caps, plateaus and cosines are no Gaussians.
// For the subtraction each element may take phi at a few sizes, as patterns' elements differ.
// Subtracting H along the normals removes the bumps and their mean height; everything the
// model does not explain stays as it was, so detail of the surface itself at the bumps' scale
// is kept (a lowpass would remove it too).
#pragma once

#include "core/filter/filter.h"
#include "core/types.h"

#include <vector>

namespace geofilter {

struct BumpPatternReport {
    int side = 0;             // +1: the selected bump points outwards (along the normals), -1: inwards, 0: undecided
    int candidates = 0;       // places where the removed detail peaks on the bumps' side
    int bumps = 0;            // of those, bumps of the pattern (height at least a third of the selected one's)
    int opposite = 0;         // elements of the other sign (dents among bumps, bumps among dents), as high
    double width = 0;         // w of the fitted Gaussian profile (where a learned one started)
    bool learned_profile = false;  // the profile's shape was learned from the selected bump and its neighbours
    double selected_height = 0;  // a of the selected bump
    double removed_volume = 0;   // the integral of H over the surface
    bool removed = false;     // false: no pattern explains the selected bump, the input was returned
    // Area-weighted RMS of the fit's residual near the selected bump and its nearest peaks,
    // relative to what varies there about the fitted offset.
    double unexplained = 0;
    double unexplained_one_sign = 0;  // the same with the selected side's elements alone (= unexplained when opposite is 0)
    // The same share across the whole surface, for a pattern of both signs (0 when not
    // measured: one sign, or the fit stopped before the whole pattern).
    double unexplained_everywhere = 0;
};


// Selected bump's width search: w from bump_width_range[0] to [1] times the measured radius.
constexpr double bump_width_range[2] = {0.5, 2.0};
// A peak is a bump of the pattern when its fitted height is at least this share of the
// selected bump's: smaller peaks are the surface's own detail, or noise, and stay.
constexpr double bump_height_share = 1.0 / 3.0;
// Above this share of what varies about the fitted offset within two radii of the selected
// peak and its six nearest left unexplained, the pattern is not one of Gaussian bumps on a
// smoother surface and nothing is subtracted. Measured (docs/results.md section 4): 0.04-0.15 on
// the procedural spheres and torus, 0.46 on bumps of another (cosine) profile, which are still
// mostly removed; 0.45-0.93 on the five scans with a texture of bumps, whose own detail at the
// bumps' size is about as large as the bumps.
constexpr double bump_max_unexplained = 0.5;
// Elements of the sign opposite to the selected bump's (dents among bumps) are fitted on what
// the selected side's fit leaves, and kept when that cuts the unexplained share to at most
// this fraction of what it was. On the tuning half of experiments/generalize_denoise's feature
// families the one pattern of bumps and dents whose fit was kept went from 0.41 to 0.25 (0.62);
// single-sign patterns moved to 0.89-1.0, the unit test's cosine caps to 0.93.
constexpr double bump_opposite_gain = 0.75;
// The sizes, relative to the fitted profile's, that each element of the subtracted pattern
// may take in combination (a non-negative height at each): patterns' elements differ in size,
// and the generalization protocol's spread their radii by +-30 %. Only the 1 judges whether
// there is a pattern at all.
constexpr double element_sizes[] = {0.8, 1.0, 1.25};
// Nor is a selected bump lower than this share of its radius: that is a flat patch.
constexpr double bump_min_height = 1e-3;

// `lowpassed` is the lowpass `g` (applied with `options`) of `input` (same triangles) that
// removed bumps of `bump_radius` (the selected bump's measured radius); `bump_faces` the
// selected bump. `options` also serve the lowpass of single bumps (fields of unit height). Returns `input` with
// the modelled pattern subtracted along the lowpassed surface's normals, or `input` itself
// when the model leaves more than bump_max_unexplained unexplained around the selected bump,
// or (elements of both signs) across the whole surface, in the fit or as the lowpass itself
// sees the pattern to subtract, or the selected bump is lower than bump_min_height of its
// radius (report->removed says which). Vertices in no face stay. Throws Error on an empty
// selection or a radius that is not a positive number.
Points remove_bump_pattern(const Points& input, const Points& lowpassed, const Triangles& triangles,
                           const std::vector<int>& bump_faces, double bump_radius, const TransferFunction& g,
                           const FilterOptions& options, BumpPatternReport* report = nullptr);

} // namespace geofilter
