#include "core/mesh/orientation.h"

#include <algorithm>
#include <vector>

namespace geofilter {

ConsistentOrientation orient_consistently(const Triangles& triangles, Eigen::Index vertex_count) {
    const Eigen::Index faces = triangles.rows();
    const auto usable = [&](Eigen::Index f) {
        for (int k = 0; k < 3; ++k)
            if (triangles(f, k) < 0 || triangles(f, k) >= vertex_count || triangles(f, k) == triangles(f, (k + 1) % 3))
                return false;
        return true;
    };
    // Each face's edge k (slot 3 f + k) filed under its smaller end: the faces of one edge meet
    // in that vertex's few entries, without sorting every edge of the mesh.
    struct Side {
        int high;
        int slot;
        bool forwards;  // runs from the smaller end to the larger
    };
    std::vector<int> start(static_cast<size_t>(vertex_count) + 1, 0);
    for (Eigen::Index f = 0; f < faces; ++f)
        if (usable(f))
            for (int k = 0; k < 3; ++k) ++start[static_cast<size_t>(std::min(triangles(f, k), triangles(f, (k + 1) % 3))) + 1];
    for (size_t v = 0; v + 1 < start.size(); ++v) start[v + 1] += start[v];
    std::vector<Side> sides(static_cast<size_t>(start.back()));
    std::vector<int> filled(start.begin(), start.end() - 1);
    for (Eigen::Index f = 0; f < faces; ++f) {
        if (!usable(f)) continue;
        for (int k = 0; k < 3; ++k) {
            const int a = triangles(f, k), b = triangles(f, (k + 1) % 3);
            sides[static_cast<size_t>(filled[static_cast<size_t>(std::min(a, b))]++)] = {std::max(a, b), static_cast<int>(3 * f + k), a < b};
        }
    }
    // Across each slot: the face on the other side of a two-face edge (-1: none), and whether
    // the two run it the same way (then one is wound against the other).
    std::vector<Eigen::Index> across(static_cast<size_t>(3 * faces), -1);
    std::vector<bool> same_way(static_cast<size_t>(3 * faces), false);
    for (size_t v = 0; v + 1 < start.size(); ++v)
        for (int i = start[v]; i < start[v + 1]; ++i) {
            int match = -1, count = 1;
            for (int j = start[v]; j < start[v + 1]; ++j)
                if (j != i && sides[static_cast<size_t>(j)].high == sides[static_cast<size_t>(i)].high) {
                    match = j;
                    ++count;
                }
            if (count != 2) continue;
            const Side& x = sides[static_cast<size_t>(i)];
            const Side& y = sides[static_cast<size_t>(match)];
            if (x.slot / 3 == y.slot / 3) continue;
            across[static_cast<size_t>(x.slot)] = y.slot / 3;
            same_way[static_cast<size_t>(x.slot)] = x.forwards == y.forwards;
        }

    ConsistentOrientation out{triangles, 0, 0};
    std::vector<signed char> turn(static_cast<size_t>(faces), -1);  // -1: not reached yet
    std::vector<Eigen::Index> patch;
    for (Eigen::Index seed = 0; seed < faces; ++seed) {
        if (turn[static_cast<size_t>(seed)] >= 0) continue;
        patch.assign(1, seed);
        turn[static_cast<size_t>(seed)] = 0;
        bool orientable = true;
        for (size_t next = 0; next < patch.size(); ++next) {
            const Eigen::Index f = patch[next];
            for (int k = 0; k < 3; ++k) {
                const auto slot = static_cast<size_t>(3 * f + k);
                const Eigen::Index g = across[slot];
                if (g < 0) continue;
                const signed char wanted = static_cast<signed char>(turn[static_cast<size_t>(f)] ^ (same_way[slot] ? 1 : 0));
                signed char& t = turn[static_cast<size_t>(g)];
                if (t < 0) {
                    t = wanted;
                    patch.push_back(g);
                } else if (t != wanted) {
                    orientable = false;
                }
            }
        }
        if (!orientable) {
            ++out.non_orientable;
            continue;
        }
        const auto turned = static_cast<size_t>(std::count_if(patch.begin(), patch.end(), [&](Eigen::Index f) { return turn[static_cast<size_t>(f)] == 1; }));
        const signed char turn_these = 2 * turned > patch.size() ? 0 : 1;  // the minority's winding is turned
        for (Eigen::Index f : patch)
            if (turn[static_cast<size_t>(f)] == turn_these) {
                std::swap(out.triangles(f, 1), out.triangles(f, 2));
                ++out.turned;
            }
    }
    return out;
}

} // namespace geofilter
