#include "core/denoise/noise_variance.h"
#include "core/design/butterworth.h"
#include "core/filter/filter_cache.h"
#include "core/mesh/surface_measures.h"

#include <algorithm>
#include <random>
#include <vector>

namespace geofilter {

namespace {

constexpr double chi_square_1_median = 0.454936423119572;  // the median of a chi-square variable with one degree of freedom

} // namespace

NoiseVariance estimate_noise_variance(const Points& points, const Triangles& triangles, const FilterOptions& options) {
    const Eigen::MatrixXd normal = smoothed_vertex_normals(points, triangles);
    const double h = mean_edge_length(points, triangles);
    const double size = bounding_box_diagonal(points);
    std::mt19937_64 random(20261203);
    Eigen::VectorXd sign(points.rows());
    for (Eigen::Index i = 0; i < sign.size(); ++i) sign[i] = (random() >> 63) ? 1.0 : -1.0;

    FilterOptions o = options;
    o.op = Operator::Umbrella;
    o.progress = nullptr;
    // The umbrella ignores the positions, so the lowpass is linear and the probe can be a full
    // edge length: (F(y + h b n) - F(y)) / h is F(b n) to the solver's tolerance, set well below.
    o.tolerance = std::min(options.tolerance, 1e-4 * h / size);
    const TransferFunction finest = design_butterworth_lowpass(1.0, 4);
    FilterCache cache;
    const Points f = apply_filter(points, triangles, finest, o, nullptr, &cache);
    const Points f_probe = apply_filter(points + h * (sign.asDiagonal() * normal), triangles, finest, o, nullptr, &cache);

    std::vector<double> squared;
    squared.reserve(static_cast<std::size_t>(points.rows()));
    double divergence = 0, kept = 0;
    int vertices = 0;
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
        if (normal.row(i).squaredNorm() == 0) continue;
        ++vertices;
        const double residual = (points.row(i) - f.row(i)).dot(normal.row(i));
        const double response = (f_probe.row(i) - f.row(i)).dot(normal.row(i)) / h;
        squared.push_back(residual * residual);
        divergence += sign[i] * response;
        kept += response * response;
    }
    if (vertices == 0) throw Error("the mesh has no face of positive area to estimate its noise on");
    NoiseVariance out;
    out.degrees_of_freedom = divergence / vertices;
    out.kept = kept / vertices;
    // n - 2 dof + kept is the expected |(I - S) b|^2 over the probe: positive for any lowpass
    // with gains in [0, 1]; guarded against a probe that came out otherwise.
    const double removed = std::max(1.0 - 2.0 * out.degrees_of_freedom + out.kept, 1e-3);
    // The median, not the mean, of the squared residuals: where the clean mesh's own finest
    // detail passes the band too (sharp edges, fingers), those vertices' residuals are detail,
    // not noise, and they are a minority the median ignores. Gaussian noise's squared residual
    // has the median 0.4549 of a chi-square with one degree of freedom times its variance.
    const auto middle = squared.begin() + static_cast<std::ptrdiff_t>(squared.size() / 2);
    std::nth_element(squared.begin(), middle, squared.end());
    out.along_normals = *middle / chi_square_1_median / removed;
    return out;
}

} // namespace geofilter
