#include "core/solve/cascade.h"

#include <algorithm>
#include <cmath>

namespace geofilter::detail {

namespace {

double polynomial_at(const std::vector<double>& c, double s) {
    double value = 0;
    for (auto it = c.rbegin(); it != c.rend(); ++it) value = value * s + *it;
    return value;
}

struct Stage {
    size_t numerator;   // index into g.numerator, or npos
    size_t first_pole;  // index into g.poles of the group solved after that numerator, or npos
    bool pair;
};

constexpr size_t none = static_cast<size_t>(-1);

std::vector<Stage> stages_of(const TransferFunction& g) {
    std::vector<Stage> stages;
    size_t next_pole = 0, next_numerator = 0;
    while (next_pole < g.poles.size() || next_numerator < g.numerator.size()) {
        Stage stage{none, none, false};
        if (next_numerator < g.numerator.size()) stage.numerator = next_numerator++;
        if (next_pole < g.poles.size()) {
            stage.first_pole = next_pole;
            stage.pair = g.poles[next_pole].imag() != 0;
            next_pole += stage.pair ? 2 : 1;
        }
        stages.push_back(stage);
    }
    return stages;
}

// |gain * (the factors of the stages after `after`)(s)|, the amplification an error made in
// stage `after`'s pole solve goes through.
double remaining_gain(const TransferFunction& g, const std::vector<Stage>& stages, size_t after, double s) {
    std::complex<double> value(g.gain, 0);
    for (size_t k = after + 1; k < stages.size(); ++k) {
        if (stages[k].numerator != none) value *= polynomial_at(g.numerator[stages[k].numerator], s);
        if (stages[k].first_pole != none) {
            value /= s - g.poles[stages[k].first_pole];
            if (stages[k].pair) value /= s - g.poles[stages[k].first_pole + 1];
        }
    }
    return std::abs(value);
}

double largest_remaining_gain(const TransferFunction& g, const std::vector<Stage>& stages, size_t after, double s_max) {
    // A log grid over the spectrum, plus the points where a resonant pair peaks (s = Re r).
    std::vector<double> samples = {0.0, s_max};
    const int count = 2000;
    const double lo = std::log(s_max * 1e-9), hi = std::log(s_max);
    for (int i = 0; i <= count; ++i) samples.push_back(std::exp(lo + (hi - lo) * i / count));
    for (const auto& p : g.poles)
        if (p.real() > 0 && p.real() < s_max) samples.push_back(p.real());
    double largest = 0;
    for (double s : samples) largest = std::max(largest, remaining_gain(g, stages, after, s));
    return largest;
}

} // namespace

double spectrum_upper_bound(const SparseMatrix& symmetric) {
    Eigen::VectorXd row_sums = Eigen::VectorXd::Zero(symmetric.rows());
    for (Eigen::Index col = 0; col < symmetric.outerSize(); ++col)
        for (SparseMatrix::InnerIterator it(symmetric, col); it; ++it) row_sums[it.row()] += std::abs(it.value());
    return row_sums.size() ? row_sums.maxCoeff() : 0.0;
}

double factor_shift_for(std::complex<double> pole) { return pole.imag() == 0 ? -pole.real() : std::abs(pole); }

double pair_operator_lower_bound(std::complex<double> r) {
    // |s - r|^2 = (s - Re r)^2 + (Im r)^2 is smallest at s = max(Re r, 0).
    const double nearest = std::max(r.real(), 0.0);
    return std::norm(std::complex<double>(nearest, 0) - r);
}

Eigen::MatrixXd apply_cascade(const TransferFunction& g, const Eigen::MatrixXd& q, double allowed_error,
                              double spectrum_max, PoleGroupSolver& solver) {
    const std::vector<Stage> stages = stages_of(g);
    size_t groups = 0;
    for (const auto& stage : stages) groups += stage.first_pole != none;
    const double s_max = std::max(spectrum_max, 1e-300);

    Eigen::MatrixXd y = q;
    size_t solved = 0;
    for (size_t k = 0; k < stages.size(); ++k) {
        const Stage& stage = stages[k];
        if (stage.numerator != none) y = solver.polynomial(g.numerator[stage.numerator], y);
        if (stage.first_pole == none) continue;
        const double amplification = largest_remaining_gain(g, stages, k, s_max);
        const double share = allowed_error / static_cast<double>(groups) / std::max(amplification, 1e-300);
        const double progress = 0.1 + 0.8 * static_cast<double>(solved++) / static_cast<double>(groups);
        const std::complex<double> pole = g.poles[stage.first_pole];
        y = stage.pair ? solver.conjugate_pair(pole, y, share, progress) : solver.real_pole(pole.real(), y, share, progress);
    }
    y *= g.gain;
    return y;
}

} // namespace geofilter::detail
