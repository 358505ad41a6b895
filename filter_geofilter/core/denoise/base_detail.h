// What a lowpass at a bump's size removes besides the bumps.
#pragma once

#include "core/operators/laplace.h"
#include "core/types.h"

#include <vector>

namespace geofilter {

// A lowpass cut at a bump's size removes the bumps and, with them, the base surface's own
// detail at that size and its mean level under a pattern of one sign (dents covering a third
// of a torus pull the lowpass inwards by their mean depth). What it removed, read along the
// normals, is then the bumps standing out of a smoother field: the base's share. That field is
// fitted by penalised least squares, the bumps weighted down: at each round the vertices whose
// removed height stands out of the current field by more than base_detail_bump_share of the
// selected bump's (either way: patterns of bumps and dents) weigh base_detail_bump_weight, the
// rest 1, until under base_detail_settled of them change. The penalty is the squared
// Laplacian, (lambda^2) K M^-1 K with lambda = radius^2 / 2, so the fitted field has the gain
// 1 / (1 + (s / sc)^2), half at the bump's own frequency sc = 2 / radius^2: the base's detail
// passes, and under the bumps the field is bridged as a thin plate. (Asymmetric least squares,
// Eilers & Boelens 2005, on a surface and weighted both ways.)
// Chosen on the tuning half of experiments/generalize_denoise (docs/denoise.md), on nine of
// its spheres and tori: a share of 0.3 left less than 0.1 in eight (0.1 also bridged the
// base's own detail near the bumps, and the result kept part of the bumps' volume); the
// weight 0.02 was not varied. Bumps lower than the share, and their tails, stay in the field.
constexpr double base_detail_bump_share = 0.3;
constexpr double base_detail_bump_weight = 0.02;
constexpr double base_detail_settled = 1e-3;
constexpr int base_detail_max_rounds = 30;

struct BaseDetailReport {
    int rounds = 0;
    double bump_area_share = 0;  // share of the surface's area weighted down as bumps at the end
    double selected_height = 0;  // how far the selected bump stands out of the first field
};

// `removed`: per vertex, the height a lowpass removed along the normals; `laplacian`: of the
// lowpassed surface; `selected`: the selected bump's vertices. Returns the base's share of
// `removed`. Vertices of zero mass (in no face) get 0.
Eigen::VectorXd base_detail(const Eigen::VectorXd& removed, const Laplacian& laplacian, double radius,
                            const std::vector<int>& selected, BaseDetailReport* report = nullptr);

// `lowpassed` (a lowpass of `input` at the bumps' size) with the base's detail that it removed
// put back along its vertex normals: base_detail of (input - lowpassed) . n, on the cotangent
// Laplacian of `lowpassed`, the selected bump's vertices those of `bump_faces`. Vertices on
// an open boundary keep their `lowpassed` positions (Denoise holds them for a selected bump).
Points with_base_detail(const Points& input, const Points& lowpassed, const Triangles& triangles,
                        const std::vector<int>& bump_faces, double radius, BaseDetailReport* report = nullptr);

} // namespace geofilter
