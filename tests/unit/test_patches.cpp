// Parts of a mesh (core/denoise/patches.h) and Denoise's scoring on patches of a large mesh: the
// patches' interior is where a lowpass run on them is the whole mesh's, and the lowpass
// chosen there denoises the whole mesh as well as the one chosen on all of it.
#include "core/denoise/denoise.h"
#include "core/denoise/patches.h"
#include "core/mesh/surface_measures.h"
#include "shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <limits>
#include <set>

using namespace geofilter;

namespace {

// Edge hops from the vertices outside `inside` (breadth first over the faces' edges).
std::vector<int> hops_from_outside(const Triangles& triangles, Eigen::Index n, const std::vector<bool>& inside) {
    std::vector<std::set<int>> adjacent(static_cast<size_t>(n));
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        for (int k = 0; k < 3; ++k) {
            const int a = triangles(f, k), b = triangles(f, (k + 1) % 3);
            adjacent[a].insert(b);
            adjacent[b].insert(a);
        }
    std::vector<int> hops(static_cast<size_t>(n), std::numeric_limits<int>::max());
    std::deque<int> queue;
    for (int v = 0; v < n; ++v)
        if (!inside[v]) {
            hops[v] = 0;
            queue.push_back(v);
        }
    while (!queue.empty()) {
        const int v = queue.front();
        queue.pop_front();
        for (int w : adjacent[v])
            if (hops[w] > hops[v] + 1) {
                hops[w] = hops[v] + 1;
                queue.push_back(w);
            }
    }
    return hops;
}

} // namespace

TEST(Patches, InducedSubmeshKeepsTheFacesWithAllCornersInTheSet) {
    const Mesh m = grid(4, 1.0);  // 25 vertices, 32 faces
    const std::vector<int> vertices{6, 7, 8, 11, 12, 13, 16, 17, 18};  // the inner 3 x 3 block
    const Submesh part = induced_submesh(m.points, m.triangles, vertices);
    EXPECT_EQ(part.vertex, vertices);
    EXPECT_EQ(part.triangles.rows(), 8);  // the 2 x 2 squares between them, two faces each
    for (size_t i = 0; i < vertices.size(); ++i) EXPECT_EQ(part.points.row(i), m.points.row(vertices[i]));
    std::set<std::array<int, 3>> expected, got;
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
        std::array<int, 3> t{m.triangles(f, 0), m.triangles(f, 1), m.triangles(f, 2)};
        if (std::all_of(t.begin(), t.end(), [&](int v) { return std::count(vertices.begin(), vertices.end(), v) > 0; }))
            expected.insert(t);
    }
    for (Eigen::Index f = 0; f < part.triangles.rows(); ++f)
        got.insert({vertices[part.triangles(f, 0)], vertices[part.triangles(f, 1)], vertices[part.triangles(f, 2)]});
    EXPECT_EQ(got, expected);
}

TEST(Patches, CountedVerticesLieAtLeastTheMarginInsideThePatches) {
    const Mesh m = torus(200, 100, 1.0, 0.4);  // 20,000 vertices
    const int count = 4, size = 2000, margin = 5;
    const ScoringPatches p = scoring_patches(m.triangles, m.points, count, size, margin);
    EXPECT_EQ(p.patches, count);
    EXPECT_GE(p.mesh.vertex.size(), static_cast<size_t>(size));
    EXPECT_LT(p.mesh.vertex.size(), static_cast<size_t>(count * 2 * size));  // whole rings, not the mesh
    std::vector<bool> inside(static_cast<size_t>(m.points.rows()), false);
    for (int v : p.mesh.vertex) inside[v] = true;
    const std::vector<int> hops = hops_from_outside(m.triangles, m.points.rows(), inside);
    size_t counted = 0;
    for (size_t i = 0; i < p.mesh.vertex.size(); ++i) {
        // A cut vertex (next to the outside) is 1 hop out and 0 rings from the cut.
        EXPECT_EQ(p.counted[i], hops[p.mesh.vertex[i]] >= margin + 1) << "vertex " << p.mesh.vertex[i];
        counted += p.counted[i];
    }
    EXPECT_GT(counted, p.mesh.vertex.size() / 2);
    // Spread: no two seeds' patches merged into one blob (4 separate parts of the torus).
    EXPECT_GE(p.mesh.vertex.size(), static_cast<size_t>(count * size));
}

TEST(Patches, PatchesThatHoldTheWholeMeshCountEveryVertex) {
    const Mesh m = icosphere(3, 1.0);  // 642 vertices
    const ScoringPatches p = scoring_patches(m.triangles, m.points, 4, 1000, 10);
    EXPECT_EQ(p.mesh.vertex.size(), static_cast<size_t>(m.points.rows()));
    EXPECT_EQ(p.mesh.triangles.rows(), m.triangles.rows());
    EXPECT_EQ(std::count(p.counted.begin(), p.counted.end(), true), m.points.rows());
}

TEST(Patches, SeedsSkipScanDebris) {
    // Ten specks of debris (a tetrahedron each) numbered before a sphere: the first seed
    // would be the first vertex in a face, and each unreached speck would be seeded next.
    const Mesh sphere = icosphere(4, 1.0);  // 2562 vertices
    const int specks = 10;
    Mesh m;
    m.points.resize(4 * specks + sphere.points.rows(), 3);
    m.triangles.resize(4 * specks + sphere.triangles.rows(), 3);
    for (int k = 0; k < specks; ++k) {
        const Eigen::RowVector3d at(3.0 + k, 0, 0);
        m.points.row(4 * k) = at;
        m.points.row(4 * k + 1) = at + Eigen::RowVector3d(0.01, 0, 0);
        m.points.row(4 * k + 2) = at + Eigen::RowVector3d(0, 0.01, 0);
        m.points.row(4 * k + 3) = at + Eigen::RowVector3d(0, 0, 0.01);
        const int b = 4 * k;
        m.triangles.row(4 * k) << b, b + 2, b + 1;
        m.triangles.row(4 * k + 1) << b, b + 1, b + 3;
        m.triangles.row(4 * k + 2) << b, b + 3, b + 2;
        m.triangles.row(4 * k + 3) << b + 1, b + 2, b + 3;
    }
    m.points.bottomRows(sphere.points.rows()) = sphere.points;
    m.triangles.bottomRows(sphere.triangles.rows()) = sphere.triangles.array() + 4 * specks;
    const int count = 4, size = 200;
    const ScoringPatches p = scoring_patches(m.triangles, m.points, count, size, 3);
    EXPECT_EQ(p.patches, count);
    for (int v : p.mesh.vertex) EXPECT_GE(v, 4 * specks) << "a patch on debris vertex " << v;
    EXPECT_GE(p.mesh.vertex.size(), static_cast<size_t>(count * size));
    // A mesh of only small parts still gets its patches, on the largest.
    const ScoringPatches only_debris = scoring_patches(m.triangles.topRows(4 * specks), m.points.topRows(4 * specks), 2, size, 1);
    EXPECT_GE(only_debris.patches, 1);
}

// The margin Denoise scores inside: there, its widest-reaching candidate lowpasses (the first
// and last: the umbrella's lowest cutoff, the geometric operator's largest radius) run on the
// patches give the whole mesh's result (the cut, a free boundary the mesh lacks, does not
// reach that far), to a small fraction of the noise; half the margin in, they do not.
TEST(Patches, InsideTheMarginTheWidestDenoiseCandidatesMatchTheWholeMesh) {
    const Mesh clean = icosphere(6, 1.0);  // 40,962 vertices
    const double h = mean_edge_length(clean.points, clean.triangles);
    const double sigma = 0.3 * h;
    const Points noisy = noised_along_normals(clean, sigma, 11);
    const ScoringPatches p = scoring_patches(clean.triangles, noisy, 4, 8000, denoise_scoring_margin);
    const ScoringPatches half = scoring_patches(clean.triangles, noisy, 4, 8000, denoise_scoring_margin / 2);
    ASSERT_EQ(p.mesh.vertex, half.mesh.vertex);
    const std::vector<DenoiseDesign> candidates = denoise_sampling_candidates(h, denoise_order, {});
    for (const DenoiseDesign& design : {candidates.front(), candidates.back()}) {
        SCOPED_TRACE(design.origin);
        FilterOptions o;
        o.op = design.op;
        const Points whole = apply_filter(noisy, clean.triangles, design.g, o);
        const Points part = apply_filter(p.mesh.points, p.mesh.triangles, design.g, o);
        const auto worst = [&](const std::vector<bool>& counted) {
            double out = 0;
            for (size_t i = 0; i < p.mesh.vertex.size(); ++i)
                if (counted[i]) out = std::max(out, (part.row(i) - whole.row(p.mesh.vertex[i])).norm());
            return out;
        };
        EXPECT_LT(worst(p.counted), 0.05 * sigma);
        EXPECT_GT(worst(half.counted), 0.1 * sigma);  // the margin is needed
    }
}

// On a mesh above the threshold (lowered here), the lowpass chosen on the patches denoises as
// well as the one chosen on the whole mesh.
TEST(Patches, DenoiseScoredOnPatchesDenoisesAsWellAsScoredOnTheWholeMesh) {
    const Mesh clean = icosphere(6, 1.0);
    const double h = mean_edge_length(clean.points, clean.triangles);
    const Points noisy = noised_along_normals(clean, 0.3 * h, 13);
    const SamplingDenoise whole = denoise_sampling_noise(noisy, clean.triangles, 4, {}, FilterOptions{});
    const SamplingDenoise patched = denoise_sampling_noise(noisy, clean.triangles, 4, {}, FilterOptions{}, 40000);
    EXPECT_EQ(whole.scoring_patches, 0);
    EXPECT_EQ(whole.scored_vertices, clean.points.rows());
    EXPECT_EQ(patched.scoring_patches, denoise_scoring_patches);
    EXPECT_GT(patched.scored_vertices, 5000);
    EXPECT_LT(patched.scored_vertices, 40000);
    const auto rms = [&](const Points& x) { return std::sqrt((x - clean.points).rowwise().squaredNorm().mean()); };
    EXPECT_LT(rms(patched.points), 1.03 * rms(whole.points))
        << whole.design.origin << " on the whole mesh, " << patched.design.origin << " on patches";
    EXPECT_LT(rms(patched.points), 0.5 * rms(noisy));  // it denoised
}
