// Maximally flat (Butterworth) filters of order n in the frequency s of the Laplacian:
// |G| stays flat up to the cutoff (no bump, so no volume change) and falls by 20 n dB per
// decade beyond it. Built as a cascade of the stages the solvers already apply (the paper's
// note on higher orders; Zhang & Fiume's factoring of rational filters).
#pragma once

#include "core/design/transfer_function.h"

namespace geofilter {

constexpr int butterworth_max_order = 8;

// G(s) = 1 / (1 + (s/sc)^n), n = 1..8. Its poles are the roots of (s/sc)^n = -1,
// p_k = sc exp(i pi (2k+1)/n), k = 0..n-1: conjugate pairs plus -sc when n is odd; none lies
// on the real half-line s >= 0 where the Laplacian's eigenvalues are. Each stage is scaled
// to unit gain at s = 0 (|p|^2 / ((s - p)(s - conj p)), sc / (s + sc)) so that intermediate
// results stay the size of the mesh. The most resonant pairs (poles nearest the positive
// axis) come first: what follows them only attenuates, so their solve error is not amplified.
// Refuses order outside 1..8 and a cutoff that is not a finite number > 0 (Error names it).
TransferFunction design_butterworth_lowpass(double cutoff, int order);

// The cutoff frequency whose eigenmodes are features of this radius (sphere-like, s = 2/r^2).
inline double frequency_of_radius(double radius) { return 2.0 / (radius * radius); }

} // namespace geofilter
