#include "core/mesh/orientation.h"

#include <algorithm>
#include <tuple>
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
    // Each face's edges as (smaller end, larger end, face, runs from smaller to larger),
    // sorted so that the faces of one edge lie side by side.
    struct Side {
        int low, high;
        Eigen::Index face;
        bool forwards;
    };
    std::vector<Side> sides;
    sides.reserve(static_cast<size_t>(3 * faces));
    for (Eigen::Index f = 0; f < faces; ++f) {
        if (!usable(f)) continue;
        for (int k = 0; k < 3; ++k) {
            const int a = triangles(f, k), b = triangles(f, (k + 1) % 3);
            sides.push_back({std::min(a, b), std::max(a, b), f, a < b});
        }
    }
    std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
        return std::tie(x.low, x.high, x.face) < std::tie(y.low, y.high, y.face);
    });
    // Across a two-face edge: the neighbour and whether the two faces run it the same way
    // (then one of them is wound against the other).
    struct Link {
        Eigen::Index face;
        bool same_way;
    };
    std::vector<std::vector<Link>> links(static_cast<size_t>(faces));
    for (size_t i = 0; i < sides.size();) {
        size_t j = i;
        while (j < sides.size() && sides[j].low == sides[i].low && sides[j].high == sides[i].high) ++j;
        if (j - i == 2 && sides[i].face != sides[i + 1].face) {
            const bool same = sides[i].forwards == sides[i + 1].forwards;
            links[static_cast<size_t>(sides[i].face)].push_back({sides[i + 1].face, same});
            links[static_cast<size_t>(sides[i + 1].face)].push_back({sides[i].face, same});
        }
        i = j;
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
            for (const Link& l : links[static_cast<size_t>(f)]) {
                const signed char wanted = static_cast<signed char>(turn[static_cast<size_t>(f)] ^ (l.same_way ? 1 : 0));
                signed char& t = turn[static_cast<size_t>(l.face)];
                if (t < 0) {
                    t = wanted;
                    patch.push_back(l.face);
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
