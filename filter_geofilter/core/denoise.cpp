#include "denoise.h"

namespace geofilter {

DenoiseDesign design_denoise_from_bump(const FeatureEllipsoid& bump, FeatureShape shape, int order, Operator op) {
    const double radius = denoise_radius_factor * bump.radius;
    const double cutoff = (shape == FeatureShape::Sphere ? 2.0 : 1.0) / (radius * radius);
    return {design_butterworth_lowpass(cutoff, order), op, cutoff,
            "the selected bump: cutoff radius " + format_number(radius) + " = " + format_number(denoise_radius_factor) +
                " x its radius " + format_number(bump.radius) +
                (shape == FeatureShape::Sphere ? " (sphere-like, s = 2/R^2)" : " (cylinder-like, s = 1/R^2)")};
}

DenoiseDesign design_denoise_from_sampling(double mean_edge_length, int order, Operator op) {
    if (op == Operator::Umbrella)
        return {design_butterworth_lowpass(denoise_vertex_cutoff, order), op, denoise_vertex_cutoff,
                "the sampling: per-vertex frequency " + format_number(denoise_vertex_cutoff) +
                    " of the umbrella operator (nothing selected)"};
    if (!(mean_edge_length > 0)) throw Error("the mesh has no edge of positive length");
    const double cutoff = 2.0 / (mean_edge_length * mean_edge_length);
    return {design_butterworth_lowpass(cutoff, order), op, cutoff,
            "the sampling: features of one mean edge length (" + format_number(mean_edge_length) +
                ") in radius, s = 2/h^2 (nothing selected)"};
}

} // namespace geofilter
