// A transfer function in factored form applied one factor at a time: numerator factor k,
// then pole group k (a real pole or a conjugate pair), then the gain. Every factor is a
// polynomial or rational function of the same Kt, so they commute; applying them in turn
// keeps intermediate magnitudes bounded. Both solvers run this one driver and differ only in
// how they solve a pole group. Internal to the core.
#pragma once

#include "core/design/transfer_function.h"

#include <complex>
#include <optional>
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
    // sum_j residues[j] (Kt - poles[j])^-1 y (G(Kt) y - G(inf) y) for poles that all call for
    // the factor at one shift (|r| of a pair, -r of a real pole: a Butterworth's), with
    // |error| (Frobenius) at most allowed_error; empty when this solver has no way to solve
    // them together (apply_factored_transfer then takes one pole group at a time).
    virtual std::optional<Eigen::MatrixXd> poles_at_one_shift(const PartialFractions&, double /*shift*/,
                                                              const Eigen::MatrixXd&, double /*allowed_error*/) {
        return std::nullopt;
    }
};

// G(Kt) q with |error| (Frobenius, in the units of q) at most allowed_error, for Kt
// symmetric with its spectrum in [0, spectrum_max]. The error budget is split evenly over
// the pole groups, each share divided by how much the factors after that group can
// amplify an error (their largest gain over the spectrum).
Eigen::MatrixXd apply_cascade(const TransferFunction& g, const Eigen::MatrixXd& q, double allowed_error,
                              double spectrum_max, PoleGroupSolver& solver);

// G(Kt) q as the factored solver applies it: a second-order G with a complex pair as
// Ginf + R/D (the iterative part then carries only the band G changes); several pole groups
// that call for the factor at one shift in partial fractions, together, where the solver can
// (PoleGroupSolver::poles_at_one_shift); anything else through apply_cascade. The one recipe of the core's factored solver and of any other engine that
// solves the same pole groups (geofilter-mpi's distributed one).
Eigen::MatrixXd apply_factored_transfer(const TransferFunction& g, const Eigen::MatrixXd& q, double allowed_error,
                                        double spectrum_max, PoleGroupSolver& solver);

// An upper bound on the largest eigenvalue of a symmetric matrix (Gershgorin: the largest
// absolute row sum).
double spectrum_upper_bound(const SparseMatrix& symmetric);

// The shift c of the real factor Kt + c I a pole calls for: |r| for a complex pole (the fastest
// CG, shifted_pair_cg.h), -r for a real one (its exact solve).
double factor_shift_for(std::complex<double> pole);

// The smallest value of |s - r|^2 over s >= 0: the smallest eigenvalue of (Kt - r)(Kt - conj r)
// can be no smaller, whatever the mesh.
double pair_operator_lower_bound(std::complex<double> r);

} // namespace geofilter::detail
