// What MUMPS's status codes mean for the exact pole-pair solves, shared by the sequential
// (mumps_complex_ldlt.cpp) and the distributed (mpi/distributed_complex_ldlt.cpp) factor.
#pragma once

#include "core/types.h"

#include <algorithm>
#include <string>

namespace geofilter {

// INFOG(1) = -8 or -9: the workspace the analysis estimated was too small for the pivoting it
// did not foresee; a larger ICNTL(14) (percent of extra room) lets the factorisation succeed.
inline bool mumps_needs_more_workspace(int infog1) { return infog1 == -8 || infog1 == -9; }
inline int mumps_larger_workspace(int icntl14) { return 2 * std::max(icntl14, 20); }

// Throws Error naming the step when INFOG(1) < 0.
inline void check_mumps(int infog1, int infog2, const char* what) {
    if (infog1 >= 0) return;
    std::string reason;
    if (infog1 == -13) reason = " (out of memory)";
    else if (infog1 == -10) reason = " (numerically singular)";
    throw Error(std::string("the complex LDL^T (MUMPS) failed in its ") + what + reason + ": INFOG(1) = " +
                std::to_string(infog1) + ", INFOG(2) = " + std::to_string(infog2));
}

} // namespace geofilter
