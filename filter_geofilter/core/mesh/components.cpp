#include "core/mesh/components.h"

#include <algorithm>
#include <numeric>
#include <tuple>

namespace geofilter {

namespace {

class DisjointSets {
public:
    explicit DisjointSets(Eigen::Index count) : parent_(static_cast<size_t>(count)) {
        std::iota(parent_.begin(), parent_.end(), 0);
    }
    void join(int a, int b) {
        a = root(a);
        b = root(b);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);
    }
    // Labels 0, 1, ... in order of first appearance.
    std::vector<int> labels() {
        std::vector<int> label(parent_.size(), -1), root_label(parent_.size(), -1);
        int next = 0;
        for (size_t v = 0; v < parent_.size(); ++v) {
            const int r = root(static_cast<int>(v));
            if (root_label[r] < 0) root_label[r] = next++;
            label[v] = root_label[r];
        }
        return label;
    }

private:
    int root(int v) {
        while (parent_[v] != v) {
            parent_[v] = parent_[parent_[v]];  // path halving keeps the trees shallow
            v = parent_[v];
        }
        return v;
    }
    std::vector<int> parent_;
};

} // namespace

std::vector<int> connected_components(const Triangles& triangles, Eigen::Index vertex_count) {
    DisjointSets sets(vertex_count);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        for (int k = 1; k < 3; ++k) sets.join(triangles(f, 0), triangles(f, k));
    return sets.labels();
}

std::vector<int> connected_components(const SparseMatrix& coupling) {
    DisjointSets sets(coupling.rows());
    for (Eigen::Index col = 0; col < coupling.outerSize(); ++col)
        for (SparseMatrix::InnerIterator it(coupling, col); it; ++it)
            sets.join(static_cast<int>(it.row()), static_cast<int>(col));
    return sets.labels();
}

int component_count(const std::vector<int>& labels) {
    int count = 0;
    for (int l : labels) count = std::max(count, l + 1);
    return count;
}

VertexFaces vertex_faces(const Triangles& triangles, Eigen::Index n, const std::vector<bool>& skip_face) {
    VertexFaces vf;
    vf.start.assign(static_cast<size_t>(n) + 1, 0);
    auto kept = [&](Eigen::Index f) { return skip_face.empty() || !skip_face[f]; };
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        if (kept(f))
            for (int k = 0; k < 3; ++k) ++vf.start[triangles(f, k) + 1];
    for (size_t v = 0; v < static_cast<size_t>(n); ++v) vf.start[v + 1] += vf.start[v];
    vf.face.resize(vf.start.back());
    std::vector<int> cursor(vf.start.begin(), vf.start.end() - 1);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        if (kept(f))
            for (int k = 0; k < 3; ++k) vf.face[cursor[triangles(f, k)]++] = static_cast<int>(f);
    return vf;
}

FaceNeighbourhoods faces_sharing_a_vertex(const Triangles& triangles, Eigen::Index vertex_count) {
    const VertexFaces around = vertex_faces(triangles, vertex_count);
    const auto faces = static_cast<std::size_t>(triangles.rows());
    FaceNeighbourhoods out;
    out.start.assign(faces + 1, 0);
    out.face.reserve(14 * faces);
    std::vector<int> seen(faces, -1);
    for (std::size_t f = 0; f < faces; ++f) {
        for (int k = 0; k < 3; ++k) {
            const auto v = static_cast<std::size_t>(triangles(static_cast<Eigen::Index>(f), k));
            for (int i = around.start[v]; i < around.start[v + 1]; ++i) {
                const int g = around.face[static_cast<std::size_t>(i)];
                if (seen[static_cast<std::size_t>(g)] == static_cast<int>(f)) continue;
                seen[static_cast<std::size_t>(g)] = static_cast<int>(f);
                out.face.push_back(g);
            }
        }
        out.start[f + 1] = static_cast<int>(out.face.size());
    }
    return out;
}

VertexNeighbours vertex_neighbours(const Triangles& triangles, Eigen::Index vertex_count) {
    VertexNeighbours out;
    out.start.assign(static_cast<size_t>(vertex_count) + 1, 0);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        for (int k = 0; k < 3; ++k) out.start[static_cast<size_t>(triangles(f, k)) + 1] += 2;
    for (size_t v = 0; v < static_cast<size_t>(vertex_count); ++v) out.start[v + 1] += out.start[v];
    std::vector<int> all(static_cast<size_t>(out.start.back()));
    std::vector<int> fill(out.start.begin(), out.start.end() - 1);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        for (int k = 0; k < 3; ++k) {
            const int v = triangles(f, k);
            all[static_cast<size_t>(fill[v]++)] = triangles(f, (k + 1) % 3);
            all[static_cast<size_t>(fill[v]++)] = triangles(f, (k + 2) % 3);
        }
    // An edge shared by two faces was listed twice: keep each neighbour once.
    out.index.reserve(all.size() / 2);
    int row_begin = 0;
    for (size_t v = 0; v < static_cast<size_t>(vertex_count); ++v) {
        const auto first = all.begin() + out.start[v], last = all.begin() + out.start[v + 1];
        std::sort(first, last);
        out.index.insert(out.index.end(), first, std::unique(first, last));
        out.start[v] = row_begin;
        row_begin = static_cast<int>(out.index.size());
    }
    out.start[static_cast<size_t>(vertex_count)] = row_begin;
    return out;
}

std::vector<bool> closed_components(const Triangles& triangles, const std::vector<int>& component, int count) {
    std::vector<bool> closed(static_cast<size_t>(count), false);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) closed[static_cast<size_t>(component[triangles(f, 0)])] = true;
    // Each directed edge as (smaller end, larger end, runs forwards): sorted, a closed
    // surface's edges come in pairs, one each way.
    struct DirectedEdge {
        int low, high;
        bool forwards;
        bool operator<(const DirectedEdge& o) const {
            return std::tie(low, high, forwards) < std::tie(o.low, o.high, o.forwards);
        }
    };
    std::vector<DirectedEdge> edges;
    edges.reserve(static_cast<size_t>(3 * triangles.rows()));
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        for (int k = 0; k < 3; ++k) {
            const int a = triangles(f, k), b = triangles(f, (k + 1) % 3);
            edges.push_back({std::min(a, b), std::max(a, b), a < b});
        }
    std::sort(edges.begin(), edges.end());
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j].low == edges[i].low && edges[j].high == edges[i].high) ++j;
        const bool one_each_way = j - i == 2 && !edges[i].forwards && edges[i + 1].forwards;
        if (!one_each_way || edges[i].low == edges[i].high) closed[static_cast<size_t>(component[edges[i].low])] = false;
        i = j;
    }
    return closed;
}

} // namespace geofilter
