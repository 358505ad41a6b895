#include "mumps_complex_ldlt.h"

#include "mumps_shifted_ldlt.h"

namespace geofilter {

namespace {

// Sequential MUMPS takes this communicator value for "no MPI".
constexpr MUMPS_INT kNoMpi = -987654;
// AMD: measured on the 1.1M-vertex scan, as fast as METIS for one pair.
constexpr int amd_ordering = 0;

} // namespace

std::unique_ptr<ComplexShiftedFactor> mumps_complex_ldlt(const SparseMatrix& kt) {
    return std::make_unique<MumpsHostLdlt>(kt, kNoMpi, amd_ordering);
}

} // namespace geofilter
