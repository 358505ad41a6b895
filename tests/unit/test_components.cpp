// Several connected components: each is its own surface, filtered about its own centroid,
// so a filter with G0 != 1 scales each part in place instead of pulling the parts together.
#include "core/filter/filter.h"
#include "core/mesh/components.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <set>

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

// Each face's neighbourhood against the definition checked pair by pair: every face with a
// corner in common, itself included, once. Two spheres joined by a vertex they share (a bow
// tie) and a face on its own.
TEST(Components, FacesSharingAVertexAreEachFacesNeighboursOnce) {
    Mesh m = joined(icosphere(1, 1.0), moved(icosphere(1, 1.0), {2, 0, 0}));
    const int shared = m.triangles(0, 0);
    m.triangles(m.triangles.rows() - 1, 0) = shared;
    m.triangles.conservativeResize(m.triangles.rows() + 1, 3);
    m.points.conservativeResize(m.points.rows() + 3, 3);
    m.points.bottomRows(3) << 5, 0, 0, 6, 0, 0, 5, 1, 0;
    const int n = static_cast<int>(m.points.rows());
    m.triangles.row(m.triangles.rows() - 1) << n - 3, n - 2, n - 1;
    const FaceNeighbourhoods around = faces_sharing_a_vertex(m.triangles, m.points.rows());
    ASSERT_EQ(around.start.size(), static_cast<std::size_t>(m.triangles.rows()) + 1);
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
        std::set<int> expected;
        for (Eigen::Index g = 0; g < m.triangles.rows(); ++g)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    if (m.triangles(f, i) == m.triangles(g, j)) expected.insert(static_cast<int>(g));
        const std::vector<int> got(around.face.begin() + around.start[static_cast<std::size_t>(f)],
                                   around.face.begin() + around.start[static_cast<std::size_t>(f) + 1]);
        EXPECT_EQ(std::set<int>(got.begin(), got.end()), expected) << "face " << f;
        EXPECT_EQ(got.size(), expected.size()) << "face " << f << ": a neighbour listed twice";
    }
}
