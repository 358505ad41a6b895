// fit_to_filtered_normals: a box's flat sides and sharp edges against noise along the normals.
#include "core/denoise/normal_fit.h"
#include "core/mesh/surface_measures.h"
#include "shapes.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <random>

using namespace geofilter;

namespace {

// The surface of the cube [-0.5, 0.5]^3 as n x n squares a side, each cut into two
// triangles, wound outwards, one vertex per lattice point.
Mesh lattice_box(int n) {
    std::map<std::array<int, 3>, int> index;
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector3i> faces;
    const auto vertex = [&](std::array<int, 3> at) {
        const auto [it, added] = index.emplace(at, static_cast<int>(points.size()));
        if (added) points.emplace_back(Eigen::Vector3d(at[0], at[1], at[2]) / n - Eigen::Vector3d::Constant(0.5));
        return it->second;
    };
    for (int axis = 0; axis < 3; ++axis)
        for (int side : {0, n}) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    std::array<int, 3> a{}, b{}, c{}, d{};
                    a[axis] = b[axis] = c[axis] = d[axis] = side;
                    a[u] = i, a[v] = j;
                    b[u] = i + 1, b[v] = j;
                    c[u] = i + 1, c[v] = j + 1;
                    d[u] = i, d[v] = j + 1;
                    const int pa = vertex(a), pb = vertex(b), pc = vertex(c), pd = vertex(d);
                    // u x v is +axis: counter-clockwise seen from outside on the far side.
                    if (side == n) faces.emplace_back(pa, pb, pc), faces.emplace_back(pa, pc, pd);
                    else faces.emplace_back(pa, pc, pb), faces.emplace_back(pa, pd, pc);
                }
        }
    return mesh_from_lists(points, faces);
}

// A vertex on the cube's edges or corners: two or more of its coordinates at +-0.5.
bool on_an_edge(const Eigen::RowVector3d& p) {
    int at_side = 0;
    for (int k = 0; k < 3; ++k) at_side += std::abs(std::abs(p[k]) - 0.5) < 1e-9;
    return at_side >= 2;
}

} // namespace

// Faces 90 degrees apart carry no weight on each other's normal (exp(-275)), so a clean box
// is already square to its smoothed normals everywhere, its edges and corners included:
// nothing moves. Averaging the normals without the angle's weight would round every edge by
// about an edge length.
TEST(NormalFit, LeavesACleanBoxAsItIs) {
    const Mesh box = lattice_box(8);
    const Points out = fit_to_filtered_normals(box.points, box.triangles, faces_sharing_a_vertex(box.triangles, box.points.rows()),
                                               normal_fit_strengths[std::size(normal_fit_strengths) - 1]);
    EXPECT_LT((out - box.points).cwiseAbs().maxCoeff(), 1e-12);
}

// Noise along the normals of a box (0.15 of its edge length): the fit brings the vertices back
// towards the sides and the edges, the faces' normals back towards the sides' (the truth), the
// edges' own vertices included: the sides' planes meet there, they are not averaged. Each
// strength in normal_fit_strengths takes more of the noise than the one before it.
TEST(NormalFit, TakesNoiseOffABoxAndKeepsItsEdges) {
    const int n = 16;
    const Mesh box = lattice_box(n);
    const Points noisy = noised_along_normals(box, 0.15 / n, 7);
    double input_edges = 0, out_edges = 0;
    int edge_vertices = 0;
    double weaker_rms = INFINITY, weaker_turn = INFINITY;
    const FaceNeighbourhoods around = faces_sharing_a_vertex(box.triangles, box.points.rows());
    for (const NormalFitStrength& strength : normal_fit_strengths) {
        SCOPED_TRACE(strength.normal_rounds);
        const Points out = fit_to_filtered_normals(noisy, box.triangles, around, strength);
        const double rms = reference::rms_distance(out, box.points);
        const double turn = reference::mean_normal_error_degrees(out, box.points, box.triangles);
        // Measured: 0.74, 0.58, 0.47, 0.38 of the input's RMS; 0.66, 0.43, 0.30, 0.16 of its normals' error.
        EXPECT_LT(rms, 0.8 * reference::rms_distance(noisy, box.points));
        EXPECT_LT(turn, 0.8 * reference::mean_normal_error_degrees(noisy, box.points, box.triangles));
        EXPECT_LT(rms, weaker_rms);  // the strengths are tried mildest first: each takes more noise
        EXPECT_LT(turn, weaker_turn);
        weaker_rms = rms;
        weaker_turn = turn;
        input_edges = out_edges = 0;
        edge_vertices = 0;
        for (Eigen::Index v = 0; v < box.points.rows(); ++v)
            if (on_an_edge(box.points.row(v))) {
                input_edges += (noisy.row(v) - box.points.row(v)).squaredNorm();
                out_edges += (out.row(v) - box.points.row(v)).squaredNorm();
                ++edge_vertices;
            }
        EXPECT_EQ(edge_vertices, 12 * (n - 1) + 8);
        EXPECT_LT(out_edges, input_edges);
    }
}
