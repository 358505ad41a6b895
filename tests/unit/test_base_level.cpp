// to_base_level: a flat lowpass of a pattern of one sign is moved back to the pattern's base.
// Checked on spheres, where the base, the lowpass's offset and the result have closed forms.
#include "core/denoise/base_level.h"
#include "shapes.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace geofilter;

namespace {

// The input: a unit sphere whose vertices with z above `top` are pushed in by `depth` (dents
// covering the cap above `top`); the smoothed: a sphere of radius `level`, where a lowpass
// that kept the mean height would put it.
Points dented(const Mesh& m, double top, double depth) {
    Points p = m.points;
    for (Eigen::Index v = 0; v < p.rows(); ++v)
        if (p(v, 2) > top) p.row(v) *= (1 - depth) / p.row(v).norm();
    return p;
}

double largest_radius_error(const Points& p, double radius) {
    return (p.rowwise().norm().array() - radius).abs().maxCoeff();
}

} // namespace

// Dents over the cap above z = 0.4 (30 % of the sphere's area): the undented 70 % is the
// base, and the median of what the lowpass removed there, 1 - 0.97 along the normals, brings
// the whole surface back to radius 1 (the polyhedron's vertices lie on the sphere).
TEST(BaseLevel, APatternCoveringLessThanHalfIsMovedBackToItsBase) {
    const Mesh m = icosphere(5, 1.0);
    const Points input = dented(m, 0.4, 0.05);
    BaseLevelReport report;
    const Points out = to_base_level(input, 0.97 * m.points, m.triangles, &report);
    EXPECT_NEAR(report.largest_offset, 0.03, 1e-3);
    EXPECT_LT(largest_radius_error(out, 1.0), 2e-3);
    // Left at the lowpass's level, it would stay 0.03 below its base.
    EXPECT_GT(largest_radius_error(0.97 * m.points, 1.0), 0.029);
}

// With the pattern over more than half of the surface (z above -0.4, 70 %), the median lies in
// the pattern: its surface is taken as the base. The rule is for patterns on a surface, not
// surfaces made of the pattern.
TEST(BaseLevel, APatternOverMostOfTheSurfaceIsTakenAsTheBase) {
    const Mesh m = icosphere(5, 1.0);
    const Points input = dented(m, -0.4, 0.05);
    const Points out = to_base_level(input, 0.97 * m.points, m.triangles);
    EXPECT_LT(largest_radius_error(out, 0.95), 2e-3);
}

// A component with a boundary keeps the lowpass's level: Denoise holds a boundary where it is
// for a selected bump, and moving the rest would tear the surface from it.
TEST(BaseLevel, AnOpenSurfaceIsLeftWhereTheLowpassPutIt) {
    const Mesh g = grid(20, 1.0);
    Points input = g.points;
    for (Eigen::Index v = 0; v < input.rows(); ++v)
        if (input(v, 0) > 0.3) input(v, 2) -= 0.05;
    Points smoothed = g.points;
    smoothed.col(2).array() -= 0.01;
    EXPECT_EQ(to_base_level(input, smoothed, g.triangles), smoothed);
}
