#include "reference_design.h"

#include <Eigen/Dense>

#include <cmath>
#include <stdexcept>

namespace geofilter::reference {

Eq15Reference eq15_reference(double s1, double s2, double G0, double G1, double Ginf) {
    // Work in t = s / s1 so that every matrix entry is O(1) whatever the unit of s; the
    // coefficients of t^k are those of s^k times s1^k. Unknowns: x = (a1, a2, b0, b1, b2) in t.
    const double t2 = s2 / s1;
    Eigen::Matrix<double, 5, 5> A = Eigen::Matrix<double, 5, 5>::Zero();
    Eigen::Matrix<double, 5, 1> rhs = Eigen::Matrix<double, 5, 1>::Zero();
    // G(0) = G0: b0 = G0.
    A(0, 2) = 1;
    rhs[0] = G0;
    // N(1) - G1 D(1) = 0: b0 + b1 + b2 - G1 (1 + a1 + a2) = 0.
    A(1, 0) = -G1; A(1, 1) = -G1; A(1, 2) = 1; A(1, 3) = 1; A(1, 4) = 1;
    rhs[1] = G1;
    // N'(1) - G1 D'(1) = 0: b1 + 2 b2 - G1 (a1 + 2 a2) = 0.
    A(2, 0) = -G1; A(2, 1) = -2 * G1; A(2, 3) = 1; A(2, 4) = 2;
    // N(t2) - D(t2) = 0: b0 + b1 t2 + b2 t2^2 - (1 + a1 t2 + a2 t2^2) = 0.
    A(3, 0) = -t2; A(3, 1) = -t2 * t2; A(3, 2) = 1; A(3, 3) = t2; A(3, 4) = t2 * t2;
    rhs[3] = 1;
    // b2 - Ginf a2 = 0.
    A(4, 1) = -Ginf; A(4, 4) = 1;

    const Eigen::FullPivLU<Eigen::Matrix<double, 5, 5>> lu(A);
    if (!lu.isInvertible()) throw std::runtime_error("eq15_reference: the five conditions are not independent");
    const Eigen::Matrix<double, 5, 1> x = lu.solve(rhs);
    if ((A * x - rhs).norm() > 1e-12 * (A.norm() * x.norm() + rhs.norm()))
        throw std::runtime_error("eq15_reference: the linear solve is inaccurate");

    Eq15Reference r;
    r.a1 = x[0] / s1;
    r.a2 = x[1] / (s1 * s1);
    r.b0 = x[2];
    r.b1 = x[3] / s1;
    r.b2 = x[4] / (s1 * s1);
    return r;
}

} // namespace geofilter::reference
