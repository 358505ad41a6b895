// Transfer functions G(s): the gain a filter applies to the eigenmode of -L with
// eigenvalue s (paper eq. 6-8). Two design routes: the second-order filter of
// eq. 15 and the pole-zero filter of eq. 16. Both end in one TransferFunction,
// a factored form the solvers can apply one factor at a time.
#pragma once

#include "core/types.h"

#include <complex>
#include <optional>
#include <string>
#include <vector>

namespace geofilter {

// The five numbers of eq. 15: G(0) = G0, G(s1) = G1 with G'(s1) = 0, G(s2) = 1, G(inf) = Ginf.
struct SecondOrderSpec {
    double s1 = 25, s2 = 50, G0 = 1, G1 = 1.1, Ginf = 0;
};

// G(s) = (b0 + b1 s + b2 s^2) / (a0 + a1 s + a2 s^2); eq. 9 is
// (a0 M + a1 K + a2 K M^-1 K) p' = (b0 M + b1 K + b2 K M^-1 K) p.
struct SecondOrderCoefficients {
    double a0, a1, a2, b0, b1, b2;
    double operator()(double s) const { return (b0 + s * (b1 + s * b2)) / (a0 + s * (a1 + s * a2)); }
};

// Eq. 16: G(s) = G0 * (prod p / prod z) * prod (s + z_i) / prod (s + p_j), every z_i, p_j > 0.
struct PoleZeroSpec {
    double G0 = 1;
    std::vector<double> zeros;
    std::vector<double> poles;
};

// G(s) = gain * prod_k numerator[k](s) / prod_j (s - poles[j]).
// numerator[k] holds ascending polynomial coefficients. Complex poles come in conjugate
// pairs stored next to each other. In a cascade (pole-zero filters) numerator[k] and the
// real pole k are applied together, which keeps intermediate magnitudes bounded.
struct TransferFunction {
    double gain = 1;
    std::vector<std::vector<double>> numerator;
    std::vector<std::complex<double>> poles;
    // Set when the function came from eq. 15: the paper's solver works on these directly.
    std::optional<SecondOrderCoefficients> second_order;

    double operator()(double s) const;
    double at_infinity() const;  // +-inf when the numerator degree exceeds the pole count
    std::string describe() const;  // coefficients / factors, for logs
};

// G(s) = at_infinity + sum_j residues[j] / (s - poles[j]): the form in which every pole is
// solved on the same right-hand side. Empty when two poles coincide (relative to the largest)
// or the numerator's degree exceeds the pole count.
struct PartialFractions {
    double at_infinity = 0;
    std::vector<std::complex<double>> poles, residues;
};
std::optional<PartialFractions> partial_fractions(const TransferFunction& g);

// Eq. 15. Refuses (Error naming the parameter) s1 <= 0, s2 <= 0, non-finite values,
// G1 = 1, G1 = Ginf, and a denominator with a root on s >= 0 (docs/paper-notes.md §4).
SecondOrderCoefficients design_coefficients(const SecondOrderSpec& spec);
TransferFunction design_second_order(const SecondOrderSpec& spec);

// Eq. 16. Refuses poles or zeros <= 0 or non-finite, no poles and no zeros is fine (G = G0).
// `warnings` receives a note when there are more zeros than poles (G grows without bound).
TransferFunction design_pole_zero(const PoleZeroSpec& spec, std::vector<std::string>* warnings = nullptr);

// Where |G| peaks, whether it overshoots |G1| or changes sign (docs/paper-notes.md §3).
struct ResponseReport {
    double peak_gain = 0;      // max |G(s)| over s >= 0 (sampled densely on a log grid + 0 + inf)
    double peak_frequency = 0; // where it is (inf when the peak is the high-frequency limit)
    double min_gain = 0;       // min G(s) (signed)
    double min_frequency = 0;
    bool changes_sign = false;
    std::vector<std::string> warnings;
};
// `reference_gain` is the gain the user asked for at the extremum (G1); 0 disables the
// overshoot note. The sampled range is [s_lo, s_hi] plus 0 and infinity.
ResponseReport analyse_response(const TransferFunction& g, double reference_gain, double s_lo, double s_hi);

// Roots of c0 + c1 s + c2 s^2 (0, 1 or 2 of them), computed without cancellation.
std::vector<std::complex<double>> quadratic_roots(double c0, double c1, double c2);

} // namespace geofilter
