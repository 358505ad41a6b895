// A lowpass applied through the Lanczos process instead of factorisations: only products with
// K, as many as the spectrum the coordinates actually reach needs. apply_filter takes it for
// the umbrella operator, whose frequencies lie in [0, 2] on any mesh.
#pragma once

#include "core/design/transfer_function.h"
#include "core/operators/laplace.h"

#include <Eigen/Core>

namespace geofilter {

struct KrylovReport {
    bool converged = true;     // false: `values` came back as given
    int iterations = 0;        // Lanczos steps, the most over the columns (each costs two products with K)
    double error_bound = 0;    // on the result's error, mass norm, Frobenius over the columns
};

// G(A) applied to each column b of `values`, A = M^-1 K, G a lowpass (G(0) = 1, finite at
// infinity) with simple poles, none on s > 0: b - q(A) A b with q(s) = (1 - G(s)) / s. q(A)
// on r = A b is taken from the Krylov space of r in the mass inner product (A is
// self-adjoint there): r's norm times V q(T) e1, T the Lanczos tridiagonal matrix, q(T) e1
// by q's partial fractions, one tridiagonal elimination per pole (stable: a complex pole
// keeps the pivots' imaginary parts away from 0, a real pole is negative). Steps are added
// until the error bound (each pole's Galerkin residual over its distance to the spectrum) is
// within `allowed_error`, in the mass norm, Frobenius over the columns, as the solvers'
// tolerance is; the smooth shape, where the coordinates hold nearly all of their size, is
// in b exactly, so the bound needs only cover the part removed. The basis is then made a
// second time to sum the result, so memory stays a few columns. Rows of zero mass are left
// as they are. Without convergence in `max_steps` steps, returns `values` as given and says
// so in the report. Throws Error when G does not qualify (krylov_lowpass_applies).
// Whether krylov_lowpass takes G: G(0) = 1, finite at infinity, at least one pole, the poles
// simple and none on s >= 0.
bool krylov_lowpass_applies(const TransferFunction& g);

Eigen::MatrixXd krylov_lowpass(const Laplacian& laplacian, const Eigen::MatrixXd& values, const TransferFunction& g,
                               double allowed_error, int max_steps = 2000, KrylovReport* report = nullptr);

} // namespace geofilter
