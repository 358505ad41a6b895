// Complex poles from one real Krylov space. With a factor of P = Kt + c I held,
// Kt - r = P - sigma I for sigma = r + c, so z = (Kt - r)^-1 y = (I - sigma T)^-1 T y with
// T = P^-1: a shifted system in T. Its Galerkin iterates come with CG on T u = T y at no extra
// solve, because a shifted system's residual stays parallel to the seed's (B. Jegerlehner,
// "Krylov space solvers for shifted linear systems", 1996), and so do those of every other
// pole solved with the same P. A pair is ((Kt - r)(Kt - conj r))^-1 y = Im(z) / Im r; each
// iteration is one solve with P on real columns, where CG on the real pair preconditioned by
// P^2 needs two and two products with Kt. At c = |r| both converge at the same rate per solve
// with P; with a factor held at another shift (a Preview's gain change) this one converges
// faster per solve (shifted_pair_rate). A Butterworth's poles all have |r| = c: its pairs,
// in partial fractions, share one space. Internal to the core.
#pragma once

#include "core/design/transfer_function.h"
#include "core/solve/pcg.h"

#include <complex>
#include <vector>

namespace geofilter::detail {

// One term of a sum formed by sum_shifted_solves: Re(weight (Kt - pole)^-1 y).
struct ShiftedTerm {
    std::complex<double> pole, weight;
};

// The sum of the terms' Re(weight (Kt - pole)^-1 y), added to `x`, with its error (Frobenius)
// at most `allowed_error`: every pole from the one Krylov space of T = (Kt + shift I)^-1, one
// solve with it per iteration whatever the number of poles. `solve_shifted` applies
// (Kt + shift I)^-1 exactly (a factor), for Kt symmetric with its spectrum in [0, inf) and
// shift > 0; a pole must not be real and >= 0. The stopping test is a bound, not an estimate:
// a term's shifted residual is zeta r_k (r_k the seed's residual), and I - sigma T is normal
// with its spectrum on the segment {1 - sigma mu : 0 <= mu <= 1 / shift}, so the term's error is
// at most |weight| |zeta r_k| / d, d that segment's distance to 0. A real pole at -shift is
// T y itself, exact. Iterations, the last bound and convergence as block_pcg reports them.
// A caller holding only its share of the rows passes `reduce_over_parts` (as to block_pcg).
PcgOutcome sum_shifted_solves(const BlockOperator& solve_shifted, double shift, const std::vector<ShiftedTerm>& terms,
                              const Eigen::MatrixXd& y, Eigen::MatrixXd& x, double allowed_error, int max_iterations,
                              const IterationObserver& observer = {}, const ColumnSumReduction& reduce_over_parts = {});

// The pair r, conj r as a term: ((Kt - r)(Kt - conj r))^-1 y = Re((-i / Im r) (Kt - r)^-1 y).
ShiftedTerm pair_term(std::complex<double> r);

// sum_j residues[j] (Kt - poles[j])^-1 y as terms, a conjugate pair as one:
// 2 Re(residue (Kt - pole)^-1 y).
std::vector<ShiftedTerm> shifted_terms(const PartialFractions& g);

// The factor by which sum_shifted_solves' error on the pair r shrinks per iteration,
// asymptotically, with a factor at `shift`: a Krylov method on a spectrum filling the segment
// from 1 to -r / shift converges by 1 / |w + sqrt(w^2 - 1)| (the larger root), w = 1 - 2 shift /
// (r + shift) the image of 0 when the segment is mapped onto [-1, 1]. At shift = |r| its square
// is CG's (sqrt(k) - 1) / (sqrt(k) + 1) on the real pair, k = 1 / sin^2(arg r / 2).
double shifted_pair_rate(std::complex<double> r, double shift);

// How many iterations sum_shifted_solves is predicted to take for the pair r with a
// factor at `shift`: an earlier solve's count scaled by the ratio of the rates' logarithms,
// or, with none (last_iterations = 0), 13 (1 + q^2) / (1 - q^2) for the rate q. At shift = |r|
// that is twice the 6.5 sqrt(k) iterations measured for CG on the real pair (11, 42 and 44
// for the lowpass, notch and exaggeration on a 416k scan), whose iterations each made two
// solves with the factor where these make one.
double shifted_pair_iterations(std::complex<double> r, double shift, int last_iterations, double last_rate);

} // namespace geofilter::detail
