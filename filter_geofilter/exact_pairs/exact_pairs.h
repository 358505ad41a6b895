// The exact complex-pole-pair solve this build offers the adapters: MUMPS's complex LDL^T
// when built with it (GEOFILTER_EXACT_PAIRS, the default), else none (every pair by CG).
// geofilter-mpi does not link this: it solves its pairs on its own distributed engine.
#pragma once

#include "core/solve/complex_shifted_factor.h"

namespace geofilter {

ComplexShiftedFactorization exact_pair_factorization();

} // namespace geofilter
