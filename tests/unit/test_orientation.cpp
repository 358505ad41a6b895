// Faces wound against their neighbours: turned back, and Denoise reads the surface through them.
#include "core/mesh/orientation.h"
#include "run_filter.h"
#include "shapes.h"

#include <gtest/gtest.h>

using namespace geofilter;

namespace {

Triangles with_faces_turned(Triangles t, int every) {
    for (Eigen::Index f = 0; f < t.rows(); f += every) std::swap(t(f, 1), t(f, 2));
    return t;
}

} // namespace

TEST(Orientation, TheFewFacesWoundAgainstTheRestAreTurnedBack) {
    const Mesh s = icosphere(3, 1.0);
    const Triangles mixed = with_faces_turned(s.triangles, 3);
    const ConsistentOrientation o = orient_consistently(mixed, s.points.rows());
    EXPECT_EQ(o.turned, (s.triangles.rows() + 2) / 3);
    EXPECT_EQ(o.non_orientable, 0);
    EXPECT_TRUE(o.triangles == s.triangles);
}

TEST(Orientation, TheWindingMostFacesHaveIsKept) {
    const Mesh s = icosphere(3, 1.0);
    // Two faces in three turned inwards: the sphere is taken as wound inwards.
    Triangles mostly_inwards = s.triangles;
    for (Eigen::Index f = 0; f < mostly_inwards.rows(); ++f)
        if (f % 3 != 0) std::swap(mostly_inwards(f, 1), mostly_inwards(f, 2));
    const ConsistentOrientation o = orient_consistently(mostly_inwards, s.points.rows());
    EXPECT_EQ(o.turned, (s.triangles.rows() + 2) / 3);
    EXPECT_TRUE(o.triangles == with_faces_turned(s.triangles, 1));
}

TEST(Orientation, AMoebiusStripAndFacesThatJoinNothingAreLeftAsTheyAre) {
    // A strip of 8 quads whose ends are joined with a half twist.
    const int n = 8;
    Triangles strip(2 * n + 2, 3);
    for (int i = 0; i < n; ++i) {
        const int a = i, b = i + 1, c = n + 1 + i, d = n + 2 + i;  // bottom row 0..n, top row n+1..2n+1
        const int bb = i + 1 == n ? n + 1 : b, dd = i + 1 == n ? 0 : d;  // the last quad meets the start twisted
        strip.row(2 * i) << a, bb, c;
        strip.row(2 * i + 1) << bb, dd, c;
    }
    strip.row(2 * n) << 0, 0, 1;       // a repeated corner
    strip.row(2 * n + 1) << 0, 1, 99;  // an index out of range
    const ConsistentOrientation o = orient_consistently(strip, 2 * n + 2);
    EXPECT_EQ(o.non_orientable, 1);
    EXPECT_EQ(o.turned, 0);
    EXPECT_TRUE(o.triangles == strip);
}

TEST(Orientation, DenoiseReadsASurfaceWithFacesWoundAgainstTheirNeighboursAsTheSurface) {
    const Mesh s = icosphere(4, 1.0);
    const Points noisy = noised_along_normals(s, 0.3 * 0.06, 7);
    const Triangles mixed = with_faces_turned(s.triangles, 4);
    const FilterSpec& spec = *find_filter("denoise");
    const ParameterValues values = default_values(spec, false);
    const std::vector<int> none;
    const RunOutput consistent = run_filter(spec, values, {noisy, s.triangles, none, {}});
    const RunOutput turned = run_filter(spec, values, {noisy, mixed, none, {}});
    ASSERT_FALSE(turned.log.empty());
    EXPECT_NE(turned.log.front().find("wound against their neighbours"), std::string::npos) << turned.log.front();
    EXPECT_LT((turned.points - consistent.points).cwiseAbs().maxCoeff(), 1e-9);
    // The enclosed volume is the noisy sphere's again (restore_volume works on closed surfaces
    // wound one way only: read as wound, this mesh encloses nothing).
    const auto volume = [&](const Points& p) {
        double v = 0;
        for (Eigen::Index f = 0; f < s.triangles.rows(); ++f)
            v += p.row(s.triangles(f, 0)).dot(p.row(s.triangles(f, 1)).cross(p.row(s.triangles(f, 2)))) / 6;
        return v;
    };
    EXPECT_NEAR(volume(turned.points), volume(noisy), 1e-9 * volume(noisy));
}
