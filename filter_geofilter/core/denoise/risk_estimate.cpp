#include "core/denoise/risk_estimate.h"
#include "core/mesh/surface_measures.h"

#include <cmath>
#include <future>
#include <random>

namespace geofilter {

RiskEstimate estimate_risk(const Points& y, const Triangles& triangles, const Smoother& smooth, double step,
                           std::uint64_t seed, const NoiseDirection& noise_direction, const Eigen::VectorXd& noise_variance, Points* smoothed, const Finish& finish,
                           const std::vector<bool>& counted, const Smoother& smooth_perturbed) {
    if (!counted.empty() && counted.size() != static_cast<size_t>(y.rows()))
        throw Error("the risk estimate's vertex flags must number the vertices (" + std::to_string(y.rows()) + "), not " +
                    std::to_string(counted.size()));
    if (!(step > 0) || !std::isfinite(step))
        throw Error("the risk estimate's probe step must be a positive number (got " + format_number(step) + ")");
    if (noise_variance.size() != y.rows())
        throw Error("the noise variance must be given per vertex (" + std::to_string(y.rows()) + "), not for " +
                    std::to_string(noise_variance.size()));
    for (Eigen::Index i = 0; i < noise_variance.size(); ++i)
        if (!(noise_variance[i] >= 0) || !std::isfinite(noise_variance[i]))
            throw Error("the noise variance must be a non-negative number (got " + format_number(noise_variance[i]) +
                        " at vertex " + std::to_string(i) + ")");
    const Eigen::MatrixXd normal = vertex_normals(y, triangles);
    std::mt19937_64 random(seed);
    const bool isotropic = noise_direction.model == NoiseModel::Isotropic;
    const bool one_direction = noise_direction.model == NoiseModel::AlongDirection;
    // Row i: the probe's direction at vertex i, +-n_i (+-the one direction) or a +-1 on each axis.
    Eigen::MatrixXd probe(y.rows(), 3);
    for (Eigen::Index i = 0; i < y.rows(); ++i) {
        if (isotropic)
            for (int k = 0; k < 3; ++k) probe(i, k) = (random() >> 63) ? 1.0 : -1.0;
        else
            probe.row(i) = ((random() >> 63) ? 1.0 : -1.0) *
                           (one_direction ? Eigen::RowVector3d(noise_direction.direction.transpose()) : Eigen::RowVector3d(normal.row(i)));
    }

    const Points perturbed = y + step * probe;
    std::future<Points> alongside;
    if (smooth_perturbed) alongside = std::async(std::launch::async, [&] { return smooth_perturbed(perturbed); });
    const Points f_raw = smooth(y);
    const Points f_perturbed = alongside.valid() ? alongside.get() : smooth(perturbed);
    const Points f = finish ? finish(y, f_raw) : f_raw;

    RiskEstimate r;
    double residual = 0, divergence = 0, weighted_divergence = 0, noise = 0;
    const int per_vertex = isotropic ? 3 : 1;
    for (Eigen::Index i = 0; i < y.rows(); ++i) {
        if (normal.row(i).squaredNorm() == 0 || (!counted.empty() && !counted[static_cast<size_t>(i)])) continue;
        ++r.vertices;
        residual += (y.row(i) - f.row(i)).squaredNorm();
        const double d = probe.row(i).dot(f_perturbed.row(i) - f_raw.row(i));
        divergence += d;
        weighted_divergence += noise_variance[i] * d;
        noise += per_vertex * noise_variance[i];
    }
    if (r.vertices == 0) throw Error("the mesh has no face of positive area to estimate a risk on");
    r.observations = per_vertex * r.vertices;
    r.residual = residual / r.vertices;
    r.degrees_of_freedom = divergence / step;
    r.unchanged = noise / r.vertices;
    r.risk = r.residual + (2 * weighted_divergence / step - noise) / r.vertices;
    if (smoothed) *smoothed = f;
    return r;
}

} // namespace geofilter
