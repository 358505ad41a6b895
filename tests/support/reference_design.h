// The test suites' one reference for the paper's second-order filter (eq. 15): the
// coefficients are found by solving the five design conditions as a linear system, not by
// the closed form the core uses. A wrong closed form (in the core or in a copy of it) then
// disagrees with this instead of agreeing with itself. Python twin: reference_design.py.
#pragma once

namespace geofilter::reference {

// G(s) = (b0 + b1 s + b2 s^2) / (a0 + a1 s + a2 s^2) with a0 = 1.
struct Eq15Reference {
    double a0 = 1, a1 = 0, a2 = 0, b0 = 0, b1 = 0, b2 = 0;
    double gain(double s) const { return (b0 + s * (b1 + s * b2)) / (a0 + s * (a1 + s * a2)); }
};

// Solves, for the unknowns a1, a2, b0, b1, b2 (a0 = 1), with N and D numerator and denominator:
//   G(0) = G0             b0 = G0
//   G(s1) = G1            N(s1) - G1 D(s1) = 0
//   G'(s1) = 0            N'(s1) - G1 D'(s1) = 0   (given the line above)
//   G(s2) = 1             N(s2) - D(s2) = 0
//   G(inf) = Ginf         b2 - Ginf a2 = 0
// Throws std::runtime_error when the system is singular (e.g. s1 = s2).
Eq15Reference eq15_reference(double s1, double s2, double G0, double G1, double Ginf);

} // namespace geofilter::reference
