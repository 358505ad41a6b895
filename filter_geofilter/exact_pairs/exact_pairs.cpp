#include "exact_pairs.h"

#ifdef GEOFILTER_HAVE_MUMPS
#include "mumps_complex_ldlt.h"
#endif

namespace geofilter {

ComplexShiftedFactorization exact_pair_factorization() {
#ifdef GEOFILTER_HAVE_MUMPS
    return mumps_complex_ldlt;
#else
    return {};
#endif
}

} // namespace geofilter
