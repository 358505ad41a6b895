#include "core/denoise/patches.h"
#include "core/mesh/components.h"

#include <algorithm>
#include <limits>

namespace geofilter {

Submesh induced_submesh(const Points& points, const Triangles& triangles, const std::vector<int>& vertices) {
    Submesh part;
    part.vertex = vertices;
    std::vector<int> local(static_cast<size_t>(points.rows()), -1);
    part.points.resize(static_cast<Eigen::Index>(vertices.size()), 3);
    for (size_t i = 0; i < vertices.size(); ++i) {
        local[static_cast<size_t>(vertices[i])] = static_cast<int>(i);
        part.points.row(static_cast<Eigen::Index>(i)) = points.row(vertices[i]);
    }
    std::vector<Eigen::Vector3i> kept;
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        const int a = local[triangles(f, 0)], b = local[triangles(f, 1)], c = local[triangles(f, 2)];
        if (a >= 0 && b >= 0 && c >= 0) kept.emplace_back(a, b, c);
    }
    part.triangles.resize(static_cast<Eigen::Index>(kept.size()), 3);
    for (size_t f = 0; f < kept.size(); ++f) part.triangles.row(static_cast<Eigen::Index>(f)) = kept[f].transpose();
    return part;
}

namespace {

constexpr int unreached = std::numeric_limits<int>::max();

// Rings from `sources` over the vertex graph, lowering `rings` where they come out smaller;
// stops a path at `stop` rings (unreached: never).
void lower_rings(const VertexNeighbours& nb, const std::vector<int>& sources, std::vector<int>& rings,
                 int stop = unreached) {
    std::vector<int> front = sources, next;
    for (int v : front) rings[static_cast<size_t>(v)] = 0;
    for (int ring = 1; !front.empty() && ring <= stop; ++ring) {
        next.clear();
        for (int v : front)
            for (int j = nb.start[v]; j < nb.start[v + 1]; ++j) {
                const int w = nb.index[static_cast<size_t>(j)];
                if (rings[static_cast<size_t>(w)] > ring) {
                    rings[static_cast<size_t>(w)] = ring;
                    next.push_back(w);
                }
            }
        front.swap(next);
    }
}

} // namespace

ScoringPatches scoring_patches(const Triangles& triangles, const Points& points, int count, int size, int margin) {
    const Eigen::Index n = points.rows();
    const VertexNeighbours nb = vertex_neighbours(triangles, n);
    const auto in_face = [&](int v) { return nb.start[v + 1] > nb.start[v]; };
    // Scans carry debris, tiny parts apart from the surface; a component no patch has reached
    // is seeded next, so each would take a patch of its own and the score would be a mean
    // over it. Seeds go only to components that can hold a whole patch or are at least
    // 1 % of the mesh (a part that large is surface, not debris), or to the largest when
    // none does.
    const std::vector<int> label = connected_components(triangles, n);
    std::vector<int> component_size(static_cast<size_t>(component_count(label)), 0);
    int vertices_in_faces = 0;
    for (int v = 0; v < n; ++v)
        if (in_face(v)) {
            ++component_size[static_cast<size_t>(label[static_cast<size_t>(v)])];
            ++vertices_in_faces;
        }
    const int largest = component_size.empty()
                            ? 0
                            : *std::max_element(component_size.begin(), component_size.end());
    const int smallest_seeded = std::min({size, std::max(1, vertices_in_faces / 100), largest});
    const auto may_seed = [&](int v) {
        return in_face(v) && component_size[static_cast<size_t>(label[static_cast<size_t>(v)])] >= smallest_seeded;
    };
    std::vector<int> from_seeds(static_cast<size_t>(n), unreached);
    std::vector<bool> inside(static_cast<size_t>(n), false);
    ScoringPatches out;
    for (int patch = 0; patch < count; ++patch) {
        int seed = -1;
        for (int v = 0; v < n; ++v)
            if (may_seed(v) && !inside[static_cast<size_t>(v)] &&
                (seed < 0 || from_seeds[static_cast<size_t>(v)] > from_seeds[static_cast<size_t>(seed)]))
                seed = v;
        if (seed < 0) break;  // the patches hold the whole mesh
        lower_rings(nb, {seed}, from_seeds);
        // Whole rings around the seed until the patch has `size` vertices.
        std::vector<int> front{seed}, next;
        inside[static_cast<size_t>(seed)] = true;
        for (int held = 1; held < size && !front.empty();) {
            next.clear();
            for (int v : front)
                for (int j = nb.start[v]; j < nb.start[v + 1]; ++j) {
                    const int w = nb.index[static_cast<size_t>(j)];
                    if (!inside[static_cast<size_t>(w)]) {
                        inside[static_cast<size_t>(w)] = true;
                        next.push_back(w);
                        ++held;
                    }
                }
            front.swap(next);
        }
        ++out.patches;
    }
    std::vector<int> vertices, cut;
    for (int v = 0; v < n; ++v) {
        if (!inside[static_cast<size_t>(v)]) continue;
        vertices.push_back(v);
        for (int j = nb.start[v]; j < nb.start[v + 1]; ++j)
            if (!inside[static_cast<size_t>(nb.index[static_cast<size_t>(j)])]) {
                cut.push_back(v);
                break;
            }
    }
    std::vector<int> from_cut(static_cast<size_t>(n), unreached);
    lower_rings(nb, cut, from_cut, margin);  // only through the patches: the cut is their rim
    out.mesh = induced_submesh(points, triangles, vertices);
    out.counted.resize(vertices.size());
    for (size_t i = 0; i < vertices.size(); ++i) out.counted[i] = from_cut[static_cast<size_t>(vertices[i])] >= margin;
    return out;
}

} // namespace geofilter
