// Several connected components: each is its own surface, filtered about its own centroid,
// so a filter with G0 != 1 scales each part in place instead of pulling the parts together.
#include "core/filter/filter.h"
#include "spectral.h"

#include <gtest/gtest.h>

using namespace geofilter;
using namespace geofilter::reference;

namespace {

Mesh joined(const Mesh& a, const Mesh& b) {
    Mesh both;
    both.points.resize(a.points.rows() + b.points.rows(), 3);
    both.points << a.points, b.points;
    both.triangles.resize(a.triangles.rows() + b.triangles.rows(), 3);
    both.triangles << a.triangles, (b.triangles.array() + static_cast<int>(a.points.rows())).matrix();
    return both;
}

Mesh moved(Mesh m, const Eigen::RowVector3d& offset) {
    m.points.rowwise() += offset;
    return m;
}

} // namespace

TEST(Components, EachPartIsScaledAboutItsOwnCentroidWhateverG0) {
    // Two bumpy spheres far apart. The reference filters each sphere alone with the dense
    // spectral filter (about its own centroid); the two-part mesh must give the same.
    Mesh a = icosphere(3, 0.5), b = icosphere(3, 0.8);
    perturb_radially(a, 0.03, 3);
    perturb_radially(b, 0.04, 5);
    a = moved(a, {-3, 1, 0.5});
    b = moved(b, {4, -2, 7});
    const Mesh both = joined(a, b);
    const Spectrum spectrum_a = spectrum_of(a), spectrum_b = spectrum_of(b);
    const double diag = bbox_diagonal(both.points);
    for (const SecondOrderSpec& spec : {SecondOrderSpec{25, 100, 0, 2, 0},   // bandpass: G0 = 0
                                        SecondOrderSpec{100, 25, 0, 1.1, 1},  // highpass: G0 = 0
                                        SecondOrderSpec{25, 50, 0.5, 1.1, 0}}) {
        SCOPED_TRACE("G0 = " + format_number(spec.G0) + ", s1 = " + format_number(spec.s1));
        const TransferFunction g = design_second_order(spec);
        FilterReport report;
        const Points out = apply_filter(both.points, both.triangles, g, {}, &report);
        EXPECT_EQ(report.components, 2);
        const Points expected_a = spectral_filter(spectrum_a, a.points, g);
        const Points expected_b = spectral_filter(spectrum_b, b.points, g);
        EXPECT_LT((out.topRows(a.points.rows()) - expected_a).rowwise().norm().maxCoeff(), 1e-6 * diag);
        EXPECT_LT((out.bottomRows(b.points.rows()) - expected_b).rowwise().norm().maxCoeff(), 1e-6 * diag);
        // The parts stay where they were: a global centroid would move them to
        // c + G0 (c_k - c), i.e. onto each other for G0 = 0.
        EXPECT_LT((out.topRows(a.points.rows()).colwise().mean() - a.points.colwise().mean()).norm(), 0.02);
        EXPECT_LT((out.bottomRows(b.points.rows()).colwise().mean() - b.points.colwise().mean()).norm(), 0.02);
    }
}
