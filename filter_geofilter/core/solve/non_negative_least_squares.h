// Non-negative least squares, the heights of Denoise's pattern fit (core/denoise/bump_pattern).
#pragma once

#include "core/types.h"

namespace geofilter {

// Non-negative least squares on the normal equations gram * a = rhs (gram symmetric positive
// semi-definite), by block principal pivoting (Kim & Park 2011, after Judice & Pires 1994):
// the unknowns taken as free are solved for exactly (sparse Cholesky), the rest held at zero;
// every free one that came out negative and every held one whose gradient asks to grow swap
// sides at once, and while that does not shrink the number of such unknowns for a few rounds
// running, only the one of highest index swaps (their backup rule, which cannot cycle). Exact
// solves matter here: in a crowded pattern raising every height at once mostly adds a smooth
// field, which the lowpass keeps and d does not see, so that direction is weakly determined
// and coordinate descent, stopped early, left the heights ~15 % low. The classical active set
// (Lawson & Hanson) frees one unknown per solve: a noisy pattern of a few thousand peaks took
// it over 100 solves per fit, stopped there unconverged, and the fits took most of a minute.
// Block swaps need each free set's solve to be definite: when one meets a null direction (more
// unknowns than the data determine) the swaps wander, and from there on the classical way
// goes on (hold the free unknowns that came out negative, else free the held one whose
// gradient asks most to grow). `free_last`: the last unknown may take either sign.
// Returns the minimiser of a' gram a / 2 - rhs' a over a >= 0 (the last entry free of sign
// with `free_last`); after 100 solves without reaching it, the last solve with its negative
// entries set to zero.
Eigen::VectorXd non_negative_solve(const SparseMatrix& gram, const Eigen::VectorXd& rhs, bool free_last = false);

} // namespace geofilter
