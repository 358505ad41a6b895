#include "cross_validation.h"
#include "surface_measures.h"

#include <cmath>
#include <limits>
#include <random>

namespace geofilter {

CrossValidationScore generalized_cross_validation(const Points& y, const Triangles& triangles, const Smoother& smooth,
                                                  double step, std::uint64_t seed, Points* smoothed) {
    if (!(step > 0) || !std::isfinite(step))
        throw Error("the cross-validation step must be a positive number (got " + format_number(step) + ")");
    const Eigen::MatrixXd normal = vertex_normals(y, triangles);
    std::mt19937_64 random(seed);
    Eigen::VectorXd probe(y.rows());
    for (Eigen::Index i = 0; i < y.rows(); ++i) probe[i] = (random() >> 63) ? 1.0 : -1.0;

    Points perturbed = y;
    for (Eigen::Index i = 0; i < y.rows(); ++i) perturbed.row(i) += step * probe[i] * normal.row(i);
    const Points f = smooth(y);
    const Points f_perturbed = smooth(perturbed);

    CrossValidationScore s;
    double residual = 0, divergence = 0;
    for (Eigen::Index i = 0; i < y.rows(); ++i) {
        if (normal.row(i).squaredNorm() == 0) continue;
        ++s.vertices;
        residual += (y.row(i) - f.row(i)).squaredNorm();
        divergence += probe[i] * normal.row(i).dot(f_perturbed.row(i) - f.row(i));
    }
    if (s.vertices == 0) throw Error("the mesh has no face of positive area to cross-validate on");
    const double n = s.vertices;
    s.residual = residual / n;
    s.degrees_of_freedom = divergence / step;
    const double kept = 1.0 - s.degrees_of_freedom / n;
    s.score = kept > 0 ? s.residual / (kept * kept) : std::numeric_limits<double>::infinity();
    if (smoothed) *smoothed = f;
    return s;
}

} // namespace geofilter
