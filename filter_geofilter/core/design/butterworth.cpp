#include "core/design/butterworth.h"

#include <cmath>

namespace geofilter {

TransferFunction design_butterworth_lowpass(double cutoff, int order) {
    if (!(std::isfinite(cutoff) && cutoff > 0))
        throw Error("the cutoff frequency must be a finite number > 0 (got " + format_number(cutoff) + ")");
    if (order < 1 || order > butterworth_max_order)
        throw Error("the order must be an integer from 1 to " + std::to_string(butterworth_max_order) + " (got " +
                    std::to_string(order) + ")");
    TransferFunction g;
    g.gain = 1;
    // k = 0 is the pair nearest the positive axis (angle pi/n), the most resonant stage.
    for (int k = 0; 2 * k + 1 < order; ++k) {
        const std::complex<double> p = std::polar(cutoff, M_PI * (2 * k + 1) / order);
        g.numerator.push_back({std::norm(p)});
        g.poles.push_back(p);
        g.poles.push_back(std::conj(p));
    }
    if (order % 2 == 1) {
        g.numerator.push_back({cutoff});
        g.poles.emplace_back(-cutoff, 0.0);
    }
    return g;
}

} // namespace geofilter
