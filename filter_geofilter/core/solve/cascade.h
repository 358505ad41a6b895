// A transfer function in factored form applied one factor at a time: numerator factor k,
// then pole group k (a real pole or a conjugate pair), then the gain. Every factor is a
// polynomial or rational function of the same Kt, so they commute; applying them in turn
// keeps intermediate magnitudes bounded. Both solvers run this one driver and differ only in
// how they solve a pole group. Internal to the core.
#pragma once

#include "core/design/transfer_function.h"

#include <complex>
#include <vector>

namespace geofilter::detail {

class PoleGroupSolver {
public:
    virtual ~PoleGroupSolver() = default;
    // c_0 y + c_1 Kt y + c_2 Kt^2 y + ...
    virtual Eigen::MatrixXd polynomial(const std::vector<double>& c, const Eigen::MatrixXd& y) = 0;
    // (Kt - r)^-1 y for a real r < 0, with |error| (Frobenius) at most allowed_error.
    virtual Eigen::MatrixXd real_pole(double r, const Eigen::MatrixXd& y, double allowed_error, double progress) = 0;
    // ((Kt - r)(Kt - conj r))^-1 y, with |error| (Frobenius) at most allowed_error.
    virtual Eigen::MatrixXd conjugate_pair(std::complex<double> r, const Eigen::MatrixXd& y, double allowed_error,
                                           double progress) = 0;
};

// G(Kt) q with |error| (Frobenius, in the units of q) at most allowed_error, for Kt
// symmetric with its spectrum in [0, spectrum_max]. The error budget is split evenly over
// the pole groups, each share divided by how much the factors after that group can
// amplify an error (their largest gain over the spectrum).
Eigen::MatrixXd apply_cascade(const TransferFunction& g, const Eigen::MatrixXd& q, double allowed_error,
                              double spectrum_max, PoleGroupSolver& solver);

// G(Kt) q as the factored solver applies it: a second-order G with a complex pair as
// Ginf + R/D (the iterative part then carries only the band G changes), anything else through
// apply_cascade. The one recipe of the core's factored solver and of any other engine that
// solves the same pole groups (geofilter-mpi's distributed one).
Eigen::MatrixXd apply_factored_transfer(const TransferFunction& g, const Eigen::MatrixXd& q, double allowed_error,
                                        double spectrum_max, PoleGroupSolver& solver);

// An upper bound on the largest eigenvalue of a symmetric matrix (Gershgorin: the largest
// absolute row sum).
double spectrum_upper_bound(const SparseMatrix& symmetric);

// The smallest value of |s - r|^2 over s >= 0: the smallest eigenvalue of (Kt - r)(Kt - conj r)
// can be no smaller, whatever the mesh.
double pair_operator_lower_bound(std::complex<double> r);

// Bounds low P <= A <= high P for the pair operator A = (Kt - r)(Kt - conj r) and the
// preconditioner P = (Kt + shift)^2, whatever the mesh: the range of |s - r|^2 / (s + shift)^2
// over s >= 0. CG on A preconditioned by P needs about sqrt(high / low) times a constant
// iterations. shift = |r| is the best real shift; then low = sin^2(arg r / 2), high = 1.
struct PreconditionedRange {
    double low, high;
};
PreconditionedRange pair_preconditioner_range(std::complex<double> r, double shift);

} // namespace geofilter::detail
