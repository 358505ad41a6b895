// A lowpass on a mesh through the Lanczos process (solve/krylov_lowpass.h) instead of the
// factored solver: for the umbrella operator, whose frequencies lie in [0, 2] on any mesh,
// a few dozen products with K per lowpass.
#pragma once

#include "core/design/transfer_function.h"
#include "core/operators/operators.h"
#include "core/solve/krylov_lowpass.h"

#include <optional>

namespace geofilter {

// G applied to the vertices of usable faces with `op`'s free-boundary operator, within
// `tolerance` of the exact filter as FilterOptions::tolerance is (a fraction of the
// bounding-box diagonal, RMS weighted by the operator's mass); the other vertices keep their
// place. Nothing when the process did not converge in `max_steps` (the caller then solves).
// Refuses a bad mesh as apply_filter does.
std::optional<Points> krylov_filter(const Points& points, const Triangles& triangles, const TransferFunction& g, Operator op,
                                    double tolerance, int max_steps, KrylovReport* report = nullptr);

} // namespace geofilter
