#include "core/design/transfer_function.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace geofilter {

namespace {

void require_finite(double v, const char* name) {
    if (!std::isfinite(v)) throw Error(std::string(name) + " must be a finite number (got " + format_number(v) + ")");
}

std::string fmt(double v) { return format_number(v); }

double poly(const std::vector<double>& c, double s) {
    double r = 0;
    for (auto it = c.rbegin(); it != c.rend(); ++it) r = r * s + *it;
    return r;
}

} // namespace

std::vector<std::complex<double>> quadratic_roots(double c0, double c1, double c2) {
    if (c2 == 0) {
        if (c1 == 0) return {};
        return {std::complex<double>(-c0 / c1, 0)};
    }
    const double disc = c1 * c1 - 4 * c2 * c0;
    if (disc >= 0) {
        // Citardauq form: the larger-magnitude root from the stable formula, the other from Vieta.
        const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
        const double r1 = q / c2;
        const double r2 = (q != 0) ? c0 / q : r1;
        return {std::complex<double>(std::min(r1, r2), 0), std::complex<double>(std::max(r1, r2), 0)};
    }
    const double re = -c1 / (2 * c2), im = std::sqrt(-disc) / (2 * std::abs(c2));
    return {std::complex<double>(re, im), std::complex<double>(re, -im)};
}

double TransferFunction::operator()(double s) const {
    std::complex<double> value(gain, 0);
    for (const auto& factor : numerator) value *= poly(factor, s);
    for (const auto& p : poles) value /= (s - p);
    return value.real();
}

std::optional<PartialFractions> partial_fractions(const TransferFunction& g) {
    const double at_infinity = g.at_infinity();
    if (!std::isfinite(at_infinity)) return std::nullopt;
    double largest = 0;
    for (const auto& p : g.poles) largest = std::max(largest, std::abs(p));
    PartialFractions out;
    out.at_infinity = at_infinity;
    for (size_t m = 0; m < g.poles.size(); ++m) {
        const std::complex<double> p = g.poles[m];
        std::complex<double> residue = g.gain;
        for (const auto& factor : g.numerator) {
            std::complex<double> value = 0;
            for (auto c = factor.rbegin(); c != factor.rend(); ++c) value = value * p + *c;
            residue *= value;
        }
        for (size_t j = 0; j < g.poles.size(); ++j) {
            if (j == m) continue;
            if (std::abs(p - g.poles[j]) <= 1e-9 * largest) return std::nullopt;
            residue /= p - g.poles[j];
        }
        out.poles.push_back(p);
        out.residues.push_back(residue);
    }
    return out;
}

double TransferFunction::at_infinity() const {
    if (second_order) {
        const auto& c = *second_order;
        if (c.a2 != 0) return c.b2 / c.a2;
        if (c.a1 != 0) return c.b2 != 0 ? std::copysign(INFINITY, c.b2 / c.a1) : c.b1 / c.a1;
    }
    int degree = 0;
    double lead = gain;
    for (const auto& f : numerator) {
        int d = static_cast<int>(f.size()) - 1;
        while (d > 0 && f[d] == 0) --d;
        degree += d;
        lead *= f[d];
    }
    degree -= static_cast<int>(poles.size());
    if (degree < 0) return 0;
    if (degree == 0) return lead;
    return std::copysign(INFINITY, lead);
}

std::string TransferFunction::describe() const {
    std::ostringstream os;
    os.precision(6);
    if (second_order) {
        const auto& c = *second_order;
        os << "G(s) = (" << c.b0 << " + " << c.b1 << " s + " << c.b2 << " s^2) / (" << c.a0 << " + " << c.a1
           << " s + " << c.a2 << " s^2)";
    } else {
        os << "G(s) = " << gain;
        for (const auto& f : numerator) {
            os << " * (";
            for (size_t k = 0; k < f.size(); ++k) os << (k ? " + " : "") << f[k] << (k ? (k == 1 ? " s" : " s^2") : "");
            os << ")";
        }
        for (const auto& p : poles) {
            if (p.imag() == 0) os << " / (s + " << -p.real() << ")";
            else if (p.imag() > 0) os << " / (s^2 + " << -2 * p.real() << " s + " << std::norm(p) << ")";  // with its conjugate
        }
    }
    os << "; poles:";
    if (poles.empty()) os << " none";
    for (const auto& p : poles) os << " " << p.real() << (p.imag() ? (p.imag() > 0 ? "+" : "") + fmt(p.imag()) + "i" : "");
    return os.str();
}

SecondOrderCoefficients design_coefficients(const SecondOrderSpec& p) {
    require_finite(p.s1, "s1");
    require_finite(p.s2, "s2");
    require_finite(p.G0, "G0");
    require_finite(p.G1, "G1");
    require_finite(p.Ginf, "Ginf");
    if (p.s1 <= 0) throw Error("s1 must be > 0 (got " + fmt(p.s1) + "): it is the frequency 2/r^2 of the feature to shape");
    if (p.s2 <= 0) throw Error("s2 must be > 0 (got " + fmt(p.s2) + "): it is the frequency where the gain returns to 1");
    if (p.G1 == 1) throw Error("G1 must differ from 1: eq. 15 divides by 1 - G1 (a gain of 1 at s1 is no filter at all)");
    if (p.G1 == p.Ginf) throw Error("G1 must differ from Ginf (both " + fmt(p.G1) + "): eq. 15 divides by G1 - Ginf");
    if (p.s1 == p.s2 && p.G1 != 1)
        throw Error("s1 and s2 must differ: G(s1) = G1 and G(s2) = 1 cannot hold at the same frequency");

    SecondOrderCoefficients c{};
    const double r01 = (p.G0 - p.G1) / (1 - p.G1);
    const double r1 = (1 - p.G0) / (1 - p.G1);
    c.a0 = 1;
    c.b0 = p.G0;
    c.a2 = -(p.G0 - p.G1) / (p.G1 - p.Ginf) / (p.s1 * p.s1);
    c.b2 = c.a2 * p.Ginf;
    c.a1 = -r01 * 2 / p.s1 - r1 / p.s2 - c.a2 * (1 - p.Ginf) / (1 - p.G1) * p.s2;
    c.b1 = r01 * (p.s2 - 2 * p.s1) / (p.s1 * p.s1) - r1 * p.G1 / p.s2 - c.a2 * p.Ginf * p.s2;

    // The denominator must stay positive on s >= 0, otherwise G has a pole at a frequency the
    // mesh may contain and a0 M + a1 K + a2 K M^-1 K is not positive definite.
    for (const auto& root : quadratic_roots(c.a0, c.a1, c.a2)) {
        if (root.imag() == 0 && root.real() >= 0) {
            std::ostringstream os;
            os.precision(4);
            os << "unstable filter: the denominator " << c.a0 << " + " << c.a1 << " s + " << c.a2
               << " s^2 has a root at s = " << root.real()
               << " >= 0, so G(s) has a pole at a frequency the mesh can contain. Change s1, s2, G1 or Ginf"
                  " (e.g. bring Ginf closer to G0, or G1 closer to 1)";
            throw Error(os.str());
        }
    }
    if (c.a2 == 0 && c.a1 < 0) throw Error("unstable filter: the denominator 1 + a1 s has a root on s > 0");
    return c;
}

TransferFunction design_second_order(const SecondOrderSpec& spec) {
    const SecondOrderCoefficients c = design_coefficients(spec);
    TransferFunction g;
    g.second_order = c;
    g.numerator = {{c.b0, c.b1, c.b2}};
    if (c.a2 != 0) {
        g.gain = 1 / c.a2;
        g.poles = quadratic_roots(c.a0, c.a1, c.a2);
    } else if (c.a1 != 0) {
        g.gain = 1 / c.a1;
        g.poles = quadratic_roots(c.a0, c.a1, 0);
    } else {
        g.gain = 1 / c.a0;
    }
    return g;
}

TransferFunction design_pole_zero(const PoleZeroSpec& spec, std::vector<std::string>* warnings) {
    require_finite(spec.G0, "G0");
    TransferFunction g;
    g.gain = spec.G0;
    for (size_t i = 0; i < spec.zeros.size(); ++i) {
        const double z = spec.zeros[i];
        const std::string name = "zero " + std::to_string(i + 1);
        require_finite(z, name.c_str());
        if (z <= 0) throw Error(name + " must be > 0 (got " + fmt(z) + "): G turns up 20 dB/decade at s = z");
        g.gain /= z;
        g.numerator.push_back({z, 1});
    }
    for (size_t i = 0; i < spec.poles.size(); ++i) {
        const double p = spec.poles[i];
        const std::string name = "pole " + std::to_string(i + 1);
        require_finite(p, name.c_str());
        if (p <= 0) throw Error(name + " must be > 0 (got " + fmt(p) + "): G turns down 20 dB/decade at s = p");
        g.gain *= p;
        g.poles.emplace_back(-p, 0);
    }
    if (spec.zeros.size() > spec.poles.size() && warnings)
        warnings->push_back("more zeros than poles: G(s) grows without bound at high frequency, so noise is amplified");
    return g;
}

ResponseReport analyse_response(const TransferFunction& g, double reference_gain, double s_lo, double s_hi) {
    ResponseReport r;
    auto visit = [&](double s, double v) {
        if (std::abs(v) > r.peak_gain) {
            r.peak_gain = std::abs(v);
            r.peak_frequency = s;
        }
        if (v < r.min_gain) {
            r.min_gain = v;
            r.min_frequency = s;
        }
    };
    r.min_gain = std::numeric_limits<double>::infinity();
    visit(0, g(0));
    const int samples = 4000;
    const double l0 = std::log(s_lo), l1 = std::log(s_hi);
    double previous = g(0);
    for (int i = 0; i <= samples; ++i) {
        const double s = std::exp(l0 + (l1 - l0) * i / samples);
        const double v = g(s);
        visit(s, v);
        if ((v < 0) != (previous < 0) && v != 0) r.changes_sign = true;
        previous = v;
    }
    const double inf_value = g.at_infinity();
    if (std::isfinite(inf_value)) {
        if ((inf_value < 0) != (previous < 0) && inf_value != 0) r.changes_sign = true;
        if (std::abs(inf_value) > r.peak_gain) {
            r.peak_gain = std::abs(inf_value);
            r.peak_frequency = INFINITY;
        }
    } else {
        r.peak_gain = INFINITY;
        r.peak_frequency = INFINITY;
        r.warnings.push_back("|G(s)| grows without bound at high frequency: noise will be amplified");
    }
    if (reference_gain != 0 && std::isfinite(r.peak_gain) && r.peak_gain > std::abs(reference_gain) * (1 + 1e-6)) {
        std::ostringstream os;
        os.precision(4);
        os << "the response overshoots: max |G| = " << r.peak_gain << " at s = " << r.peak_frequency << " exceeds |G1| = "
           << std::abs(reference_gain);
        r.warnings.push_back(os.str());
    }
    if (r.changes_sign) {
        std::ostringstream os;
        os.precision(4);
        os << "G(s) changes sign (min G = " << r.min_gain << " at s = " << r.min_frequency
           << "): modes there are flipped, not just scaled";
        r.warnings.push_back(os.str());
    }
    return r;
}

} // namespace geofilter
