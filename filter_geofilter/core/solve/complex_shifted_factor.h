// The factorisation a complex pole pair can be solved exactly with: Kt - r I for a complex r
// is complex symmetric (Kt is real symmetric), not Hermitian, so CHOLMOD, the core's only
// direct solver, cannot factorise it. Libraries outside the core provide it (MUMPS's complex
// LDL^T: exact_pairs/ sequential, mpi/ distributed); without one, every pair is solved by CG.
#pragma once

#include "core/types.h"

#include <complex>
#include <functional>
#include <memory>
#include <string>

namespace geofilter {

// What a factorisation held, in the library's own counts (for logs); zero where unknown.
struct ComplexFactorSize {
    double entries = 0;
    double megabytes_largest_process = 0, megabytes_total = 0;
};

class ComplexShiftedFactor {
public:
    virtual ~ComplexShiftedFactor() = default;
    virtual std::string name() const = 0;  // for logs: "complex LDL^T (MUMPS)"
    // Memory the next factorisation will take, in bytes, as the analysis estimated it.
    virtual double estimated_factorization_bytes() const = 0;
    // Makes a factor of Kt - r I current (computing it unless r is the shift held). Throws
    // Error if the library fails (out of memory included).
    virtual void factorize(std::complex<double> r) = 0;
    virtual bool holds(std::complex<double> r) const = 0;
    // (Kt - r I)^-1 b with the current factor.
    virtual Eigen::MatrixXcd solve(const Eigen::MatrixXcd& b) = 0;
    virtual ComplexFactorSize factor_size() const { return {}; }
    // For a factor of lower precision than the refinement it feeds: replaces it by a
    // double-precision factor of the same shift and returns true; false when it cannot (the
    // precision is double already). Collective where the factor is.
    virtual bool raise_precision() { return false; }
};

// Analyses the pattern of `kt` (which must outlive the factor) and returns a factor holder;
// throws Error if the library refuses the matrix.
using ComplexShiftedFactorization = std::function<std::unique_ptr<ComplexShiftedFactor>(const SparseMatrix& kt)>;

} // namespace geofilter
