#include "core/operators/intrinsic_delaunay.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <utility>

namespace geofilter {

namespace {

// Halfedge h = 3 f + i runs from corner i to corner i+1 of face f; the intrinsic geometry is
// the length of each halfedge (twins hold equal lengths).
struct IntrinsicMesh {
    std::vector<int> tail;       // origin vertex of each halfedge
    std::vector<int> twin;       // -1 on boundary and non-manifold edges: never flipped
    std::vector<double> length;

    static int next(int h) { return h - h % 3 + (h + 1) % 3; }
    int head(int h) const { return tail[next(h)]; }
    int face_count() const { return static_cast<int>(tail.size() / 3); }
};

IntrinsicMesh build(const Points& points, const Triangles& triangles) {
    IntrinsicMesh m;
    const int nf = static_cast<int>(triangles.rows());
    m.tail.resize(3 * nf);
    m.twin.assign(3 * nf, -1);
    m.length.resize(3 * nf);
    std::map<std::pair<int, int>, std::vector<int>> by_edge;  // undirected edge -> halfedges
    for (int f = 0; f < nf; ++f)
        for (int i = 0; i < 3; ++i) {
            const int h = 3 * f + i, a = triangles(f, i), b = triangles(f, (i + 1) % 3);
            m.tail[h] = a;
            m.length[h] = (points.row(a) - points.row(b)).norm();
            by_edge[{std::min(a, b), std::max(a, b)}].push_back(h);
        }
    for (const auto& [edge, hs] : by_edge)
        if (hs.size() == 2 && m.tail[hs[0]] != m.tail[hs[1]]) {  // manifold and consistently oriented
            m.twin[hs[0]] = hs[1];
            m.twin[hs[1]] = hs[0];
        }
    return m;
}

// Twice the area from the three lengths (Kahan's ordering of Heron's formula: accurate for
// needle triangles, where the plain formula cancels).
double twice_area(double a, double b, double c) {
    if (a < b) std::swap(a, b);
    if (a < c) std::swap(a, c);
    if (b < c) std::swap(b, c);
    const double q = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
    return 0.5 * std::sqrt(std::max(q, 0.0));
}

// Cotangent of the angle opposite halfedge h, in its face.
double cot_opposite(const IntrinsicMesh& m, int h) {
    const int h1 = IntrinsicMesh::next(h), h2 = IntrinsicMesh::next(h1);
    const double a = m.length[h], b = m.length[h1], c = m.length[h2];
    const double area2 = twice_area(a, b, c);
    return (b * b + c * c - a * a) / (2 * area2);
}

bool is_delaunay(const IntrinsicMesh& m, int h) {
    const int t = m.twin[h];
    if (t < 0) return true;
    // Opposite angles sum <= pi  <=>  cot + cot >= 0; the slack avoids flipping cocircular
    // quads back and forth (a regular grid's diagonals).
    return cot_opposite(m, h) + cot_opposite(m, t) >= -1e-10;
}

// Position of the apex opposite a segment of length l on the x axis from (0,0) to (l,0),
// at distances da from (0,0) and db from (l,0); y >= 0.
Eigen::Vector2d apex(double l, double da, double db) {
    const double x = (l * l + da * da - db * db) / (2 * l);
    return {x, std::sqrt(std::max(da * da - x * x, 0.0))};
}

// Flips the edge of h (a->b in face (a, b, c), twin b->a in face (b, a, d)) to c-d.
// Returns false (and changes nothing) when the flip would not give two proper triangles.
bool flip(IntrinsicMesh& m, int h) {
    const int t = m.twin[h];
    const int h1 = IntrinsicMesh::next(h), h2 = IntrinsicMesh::next(h1);
    const int t1 = IntrinsicMesh::next(t), t2 = IntrinsicMesh::next(t1);
    const int a = m.tail[h], b = m.tail[h1], c = m.tail[h2], d = m.tail[t2];
    if (c == d) return false;
    // Unfold the two triangles into the plane on either side of a-b.
    const double l = m.length[h];
    const Eigen::Vector2d pc = apex(l, m.length[h2], m.length[h1]);
    Eigen::Vector2d pd = apex(l, m.length[t1], m.length[t2]);
    pd.y() = -pd.y();
    const double l_cd = (pc - pd).norm();
    // The new triangles (c, a, d) and (d, b, c) must have positive area.
    if (!(twice_area(m.length[h2], m.length[t1], l_cd) > 0 && twice_area(m.length[t2], m.length[h1], l_cd) > 0))
        return false;
    // Outer halfedges: b->c (h1), c->a (h2), a->d (t1), d->b (t2).
    struct Outer { int tail, twin; double length; };
    const Outer bc{b, m.twin[h1], m.length[h1]}, ca{c, m.twin[h2], m.length[h2]}, ad{a, m.twin[t1], m.length[t1]},
        db{d, m.twin[t2], m.length[t2]};
    // Face of h becomes (d, c, a): d->c, c->a, a->d; face of t becomes (c, d, b): c->d, d->b, b->c.
    auto place = [&](int slot, const Outer& o) {
        m.tail[slot] = o.tail;
        m.twin[slot] = o.twin;
        m.length[slot] = o.length;
        if (o.twin >= 0) m.twin[o.twin] = slot;
    };
    place(h1, ca);
    place(h2, ad);
    place(t1, db);
    place(t2, bc);
    m.tail[h] = d;
    m.tail[t] = c;
    m.length[h] = m.length[t] = l_cd;
    return true;
}

} // namespace

Laplacian intrinsic_delaunay_laplacian(const Points& points, const Triangles& triangles, IntrinsicDelaunayStats* stats) {
    IntrinsicMesh m = build(points, triangles);
    const int nh = static_cast<int>(m.tail.size());
    std::deque<int> queue;
    std::vector<char> queued(nh, 0);
    for (int h = 0; h < nh; ++h)
        if (m.twin[h] > h) {
            queue.push_back(h);
            queued[h] = 1;
        }
    // Flips terminate in exact arithmetic (Bobenko & Springborn); the cap guards rounding.
    const long cap = 100L * nh + 1000;
    IntrinsicDelaunayStats s;
    while (!queue.empty() && s.flips < cap) {
        const int h = queue.front();
        queue.pop_front();
        queued[h] = 0;
        if (m.twin[h] < 0 || is_delaunay(m, h) || !flip(m, h)) continue;
        ++s.flips;
        const int t = m.twin[h];
        for (int outer : {IntrinsicMesh::next(h), IntrinsicMesh::next(IntrinsicMesh::next(h)), IntrinsicMesh::next(t),
                          IntrinsicMesh::next(IntrinsicMesh::next(t))}) {
            const int tw = m.twin[outer];
            if (tw < 0) continue;
            const int key = std::min(outer, tw);
            if (!queued[key]) {
                queued[key] = 1;
                queue.push_back(key);
            }
        }
    }
    for (int h = 0; h < nh; ++h)
        if (m.twin[h] > h && !is_delaunay(m, h)) ++s.non_delaunay_edges_left;

    const Eigen::Index n = points.rows();
    Laplacian result;
    result.mass = Eigen::VectorXd::Zero(n);
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<size_t>(nh) * 4);
    for (int h = 0; h < nh; ++h) {
        const int a = m.tail[h], b = m.head(h);
        const double half_cot = 0.5 * cot_opposite(m, h);
        entries.emplace_back(a, b, -half_cot);
        entries.emplace_back(b, a, -half_cot);
        entries.emplace_back(a, a, half_cot);
        entries.emplace_back(b, b, half_cot);
    }
    for (int f = 0; f < m.face_count(); ++f) {
        const double third = twice_area(m.length[3 * f], m.length[3 * f + 1], m.length[3 * f + 2]) / 6.0;
        for (int i = 0; i < 3; ++i) result.mass[m.tail[3 * f + i]] += third;
    }
    result.stiffness.resize(n, n);
    result.stiffness.setFromTriplets(entries.begin(), entries.end());
    if (stats) *stats = s;
    return result;
}

} // namespace geofilter
