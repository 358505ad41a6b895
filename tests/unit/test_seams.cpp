// Seams: copies of a vertex on open edges, at the same position, are filtered as one vertex.
#include "core/mesh/seams.h"
#include "filter_table.h"
#include "run_filter.h"
#include "shapes.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace geofilter;

namespace {

// The sphere cut along its equator the way a file splits a seam: the faces above it get their
// own copies of the equator's vertices, appended after the others.
struct SplitMesh {
    Mesh mesh;
    std::vector<int> original_of_copy;  // copy index - original vertex count -> original vertex
};

SplitMesh split_at_the_equator(const Mesh& whole) {
    const Eigen::Index n = whole.points.rows();
    std::vector<bool> below(static_cast<std::size_t>(n), false), above(static_cast<std::size_t>(n), false);
    std::vector<bool> upper(static_cast<std::size_t>(whole.triangles.rows()));
    for (Eigen::Index f = 0; f < whole.triangles.rows(); ++f) {
        double z = 0;
        for (int k = 0; k < 3; ++k) z += whole.points(whole.triangles(f, k), 2);
        upper[static_cast<std::size_t>(f)] = z > 0;
        for (int k = 0; k < 3; ++k) (z > 0 ? above : below)[static_cast<std::size_t>(whole.triangles(f, k))] = true;
    }
    SplitMesh out;
    std::vector<int> copy(static_cast<std::size_t>(n), -1);
    for (Eigen::Index v = 0; v < n; ++v)
        if (below[static_cast<std::size_t>(v)] && above[static_cast<std::size_t>(v)]) {
            copy[static_cast<std::size_t>(v)] = static_cast<int>(n + static_cast<Eigen::Index>(out.original_of_copy.size()));
            out.original_of_copy.push_back(static_cast<int>(v));
        }
    out.mesh.points.resize(n + static_cast<Eigen::Index>(out.original_of_copy.size()), 3);
    out.mesh.points.topRows(n) = whole.points;
    for (std::size_t c = 0; c < out.original_of_copy.size(); ++c)
        out.mesh.points.row(n + static_cast<Eigen::Index>(c)) = whole.points.row(out.original_of_copy[c]);
    out.mesh.triangles = whole.triangles;
    for (Eigen::Index f = 0; f < whole.triangles.rows(); ++f)
        if (upper[static_cast<std::size_t>(f)])
            for (int k = 0; k < 3; ++k)
                if (const int c = copy[static_cast<std::size_t>(whole.triangles(f, k))]; c >= 0) out.mesh.triangles(f, k) = c;
    return out;
}

double widest_crack(const Points& p, const SplitMesh& split) {
    const Eigen::Index n = p.rows() - static_cast<Eigen::Index>(split.original_of_copy.size());
    double widest = 0;
    for (std::size_t c = 0; c < split.original_of_copy.size(); ++c)
        widest = std::max(widest, (p.row(n + static_cast<Eigen::Index>(c)) - p.row(split.original_of_copy[c])).norm());
    return widest;
}

} // namespace

TEST(Seams, ASplitSphereIsWeldedBackToItsOwnFaces) {
    const Mesh whole = icosphere(3, 1.0);
    const SplitMesh split = split_at_the_equator(whole);
    ASSERT_GT(split.original_of_copy.size(), 20u);  // the premise: a seam all round
    const SeamWeld seams = weld_seams(split.mesh.points, split.mesh.triangles);
    EXPECT_EQ(seams.welded, static_cast<int>(split.original_of_copy.size()));
    EXPECT_TRUE(seams.triangles == whole.triangles);
}

TEST(Seams, CopiesInsideTheSurfaceOrOnlyNearlyInPlaceStayApart) {
    const Mesh whole = icosphere(3, 1.0);
    SplitMesh split = split_at_the_equator(whole);
    const Eigen::Index n = whole.points.rows();
    split.mesh.points(n, 0) += 1e-12;  // one copy a hair's breadth off: two parts that only touch
    EXPECT_EQ(weld_seams(split.mesh.points, split.mesh.triangles).welded, static_cast<int>(split.original_of_copy.size()) - 1);
    // The whole sphere (no open edge) with a loose vertex on one of its own: nothing to weld.
    Mesh loose = whole;
    loose.points.conservativeResize(n + 1, 3);
    loose.points.row(n) = whole.points.row(5);
    EXPECT_EQ(weld_seams(loose.points, loose.triangles).welded, 0);
    // A face pointing past the vertices welds nothing and is left for the filters to refuse.
    Triangles bad = split.mesh.triangles;
    bad(0, 0) = static_cast<int>(split.mesh.points.rows());
    EXPECT_EQ(weld_seams(split.mesh.points, bad).welded, 0);
}

// Every front end goes through run_filter: a seam stays closed, and the split mesh is filtered
// as the whole one. Cut apart, a lowpass at a tenth of the sphere's size opened the equator.
TEST(Seams, AFilterKeepsASeamClosedAndFiltersTheWholeSurface) {
    Mesh whole = icosphere(4, 1.0);
    perturb_radially(whole, 0.02, 3);
    const SplitMesh split = split_at_the_equator(whole);
    for (const char* name : {"lowpass", "denoise"}) {
        SCOPED_TRACE(name);
        const FilterSpec& spec = *find_filter(name);
        ParameterValues values = default_values(spec, false);
        if (std::string(name) == "lowpass") values[param::radius] = 0.1;
        const RunOutput cut = run_filter(spec, values, {split.mesh.points, split.mesh.triangles, {}, {}});
        const RunOutput joined = run_filter(spec, values, {whole.points, whole.triangles, {}, {}});
        EXPECT_EQ(widest_crack(cut.points, split), 0.0);
        EXPECT_LT((cut.points.topRows(whole.points.rows()) - joined.points).cwiseAbs().maxCoeff(), 1e-9);
        EXPECT_GT((cut.points - split.mesh.points).norm(), 0.0);  // it did filter
        bool logged = false;
        for (const auto& line : cut.log) logged |= line.rfind("seams: " + std::to_string(split.original_of_copy.size()), 0) == 0;
        EXPECT_TRUE(logged);
    }
}

// A clean box, built the way a CAD exporter writes one: six flat squares that share their
// edges' positions but not their vertices. Welded, it is one closed surface; its flat faces
// read no noise (their rings are planar), and its edges, which the finest band's lowpass drags
// into every neighbourhood of so coarse a part, are not taken for noise: Denoise returns it as
// it was. With noise on it, the noise is still read and taken out.
TEST(Seams, DenoiseLeavesACleanBoxOfSixSquaresAsItWas) {
    const Mesh square = grid(16, 1.0);  // sides of 1/16: every position exact in binary, so the copies match
    Mesh box;
    box.points.resize(6 * square.points.rows(), 3);
    box.triangles.resize(6 * square.triangles.rows(), 3);
    for (int side = 0; side < 6; ++side) {
        const int axis = side / 2;
        const double at = side % 2 ? 0.5 : -0.5;
        for (Eigen::Index v = 0; v < square.points.rows(); ++v) {
            Eigen::RowVector3d p;
            p[axis] = at;
            p[(axis + 1) % 3] = square.points(v, 0);
            p[(axis + 2) % 3] = square.points(v, 1);
            box.points.row(side * square.points.rows() + v) = p;
        }
        box.triangles.middleRows(side * square.triangles.rows(), square.triangles.rows()) =
            square.triangles.array() + static_cast<int>(side * square.points.rows());
    }
    const FilterSpec& spec = *find_filter("denoise");
    const RunOutput clean = run_filter(spec, default_values(spec, false), {box.points, box.triangles, {}, {}});
    EXPECT_EQ(clean.points, box.points);
    // The same noise on every copy of a vertex (one draw per welded vertex), 0.2 of the
    // squares' side in every direction.
    const SeamWeld seams = weld_seams(box.points, box.triangles);
    ASSERT_GT(seams.welded, 0);
    std::mt19937 random(5);
    std::normal_distribution<double> gauss(0.0, 0.2 / 16 / std::sqrt(3.0));
    Points noise(box.points.rows(), 3);
    for (Eigen::Index v = 0; v < noise.rows(); ++v)
        for (int k = 0; k < 3; ++k) noise(v, k) = gauss(random);
    Points noisy = box.points;
    for (Eigen::Index v = 0; v < noisy.rows(); ++v) noisy.row(v) += noise.row(seams.representative[static_cast<std::size_t>(v)]);
    const RunOutput out = run_filter(spec, default_values(spec, false), {noisy, box.triangles, {}, {}});
    // Read and taken out: a reading of no noise would return the noisy box as it was.
    EXPECT_LT(rms_distance(out.points, box.points), 0.9 * rms_distance(noisy, box.points));
}
