// Real scans for tests: the OFF meshes scripts/fetch-meshes.sh extracts into meshes/, and
// connected patches of them small enough for the dense spectral reference. Test-only.
#pragma once

#include "shapes.h"

#include <gtest/gtest.h>

#include <fstream>
#include <queue>
#include <string>
#include <vector>

namespace geofilter::reference {

// Reads a triangle OFF file; fails the calling test (no silent skip) when it is missing.
inline Mesh read_off(const std::string& path) {
    std::ifstream in(path);
    std::string magic;
    Mesh m;
    if (!(in >> magic) || magic != "OFF") {
        ADD_FAILURE() << path << " is missing or not an OFF file: run scripts/fetch-meshes.sh (scripts/setup.sh does)";
        return m;
    }
    long vertices = 0, faces = 0, edges = 0;
    in >> vertices >> faces >> edges;
    m.points.resize(vertices, 3);
    for (long i = 0; i < vertices; ++i) in >> m.points(i, 0) >> m.points(i, 1) >> m.points(i, 2);
    m.triangles.resize(faces, 3);
    for (long f = 0; f < faces; ++f) {
        int corners = 0;
        in >> corners >> m.triangles(f, 0) >> m.triangles(f, 1) >> m.triangles(f, 2);
        if (corners != 3) ADD_FAILURE() << path << ": face " << f << " is not a triangle";
    }
    if (!in) ADD_FAILURE() << path << " is truncated";
    return m;
}

// The faces reached by growing from `seed_face` across shared edges until `vertex_budget`
// vertices are covered, renumbered compactly, scaled to unit bounding-box diagonal.
inline Mesh patch_of(const Mesh& m, int seed_face, Eigen::Index vertex_budget) {
    std::vector<std::vector<int>> faces_of(m.points.rows());
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
        for (int k = 0; k < 3; ++k) faces_of[m.triangles(f, k)].push_back(static_cast<int>(f));
    std::vector<int> index(m.points.rows(), -1);
    std::vector<bool> taken(m.triangles.rows(), false);
    std::vector<Eigen::Vector3i> faces;
    std::vector<Eigen::RowVector3d> points;
    std::queue<int> frontier;
    frontier.push(seed_face);
    taken[seed_face] = true;
    while (!frontier.empty() && static_cast<Eigen::Index>(points.size()) < vertex_budget) {
        const int f = frontier.front();
        frontier.pop();
        Eigen::Vector3i face;
        for (int k = 0; k < 3; ++k) {
            const int v = m.triangles(f, k);
            if (index[v] < 0) {
                index[v] = static_cast<int>(points.size());
                points.push_back(m.points.row(v));
            }
            face[k] = index[v];
            for (int g : faces_of[v])
                if (!taken[g]) {
                    taken[g] = true;
                    frontier.push(g);
                }
        }
        faces.push_back(face);
    }
    Mesh patch;
    patch.points.resize(static_cast<Eigen::Index>(points.size()), 3);
    for (size_t i = 0; i < points.size(); ++i) patch.points.row(static_cast<Eigen::Index>(i)) = points[i];
    patch.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
    for (size_t f = 0; f < faces.size(); ++f) patch.triangles.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
    const double diag = (patch.points.colwise().maxCoeff() - patch.points.colwise().minCoeff()).norm();
    patch.points /= diag;
    return patch;
}

#ifdef GEOFILTER_MESHES
// A 1,500-vertex patch of the real "man" scan: irregular, with many eigenvalues near any
// resonance, and small enough for the dense spectral reference.
inline const Mesh& man_scan_patch() {
    static const Mesh patch = patch_of(read_off(GEOFILTER_MESHES "/man.off"), 0, 1500);
    return patch;
}
#endif

} // namespace geofilter::reference
