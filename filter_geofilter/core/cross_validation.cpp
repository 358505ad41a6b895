#include "cross_validation.h"
#include "surface_measures.h"

#include <cmath>
#include <limits>
#include <random>

namespace geofilter {

CrossValidationScore generalized_cross_validation(const Points& y, const Triangles& triangles, const Smoother& smooth,
                                                  double step, std::uint64_t seed, NoiseModel model,
                                                  Points* smoothed) {
    if (!(step > 0) || !std::isfinite(step))
        throw Error("the cross-validation step must be a positive number (got " + format_number(step) + ")");
    const Eigen::MatrixXd normal = vertex_normals(y, triangles);
    std::mt19937_64 random(seed);
    const bool isotropic = model == NoiseModel::Isotropic;
    // Row i: the probe's direction at vertex i, +-n_i or a +-1 on each axis.
    Eigen::MatrixXd probe(y.rows(), 3);
    for (Eigen::Index i = 0; i < y.rows(); ++i) {
        if (isotropic)
            for (int k = 0; k < 3; ++k) probe(i, k) = (random() >> 63) ? 1.0 : -1.0;
        else
            probe.row(i) = ((random() >> 63) ? 1.0 : -1.0) * normal.row(i);
    }

    const Points perturbed = y + step * probe;
    const Points f = smooth(y);
    const Points f_perturbed = smooth(perturbed);

    CrossValidationScore s;
    double residual = 0, divergence = 0;
    for (Eigen::Index i = 0; i < y.rows(); ++i) {
        if (normal.row(i).squaredNorm() == 0) continue;
        ++s.vertices;
        residual += (y.row(i) - f.row(i)).squaredNorm();
        divergence += probe.row(i).dot(f_perturbed.row(i) - f.row(i));
    }
    if (s.vertices == 0) throw Error("the mesh has no face of positive area to cross-validate on");
    s.observations = (isotropic ? 3 : 1) * s.vertices;
    s.residual = residual / s.vertices;
    s.degrees_of_freedom = divergence / step;
    const double kept = 1.0 - s.degrees_of_freedom / s.observations;
    s.score = kept > 0 ? s.residual / (kept * kept) : std::numeric_limits<double>::infinity();
    if (smoothed) *smoothed = f;
    return s;
}

} // namespace geofilter
