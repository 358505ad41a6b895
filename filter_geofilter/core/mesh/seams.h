// Seams: a surface cut along a line into two sides that each carry their own copy of the
// vertices on it. Files split vertices wherever a corner has two normals or two texture
// coordinates (a crease exported flat-shaded per side, a texture's seam, a CAD part exported
// face by face); the surface is whole, but a filter that goes by the faces sees open edges
// there, moves each side on its own and opens a crack. Welded for filtering, the seam's copies
// move as one and stay together.
#pragma once

#include "core/types.h"

#include <vector>

namespace geofilter {

struct SeamWeld {
    Triangles triangles;             // the faces with every copy replaced by its seam's first vertex
    std::vector<int> representative; // vertex -> the vertex it is filtered as (itself unless a later copy)
    int welded = 0;                  // copies replaced
};

// The vertices' indices sorted by position (x, then y, then z; ties by index): vertices at
// the same place end up side by side.
std::vector<int> order_by_position(const Points& points);

// Vertices on an open boundary (an edge of one face) at exactly equal positions are one
// vertex split by a seam: each is replaced by the lowest-numbered of them. Vertices inside the
// surface, or at positions that only nearly match, are left apart: exact copies on a
// boundary are what a file's split leaves, while a near match may be two parts that only
// touch. Faces with an index out of range or a non-finite corner weld nothing (the filters
// refuse them with their own message).
SeamWeld weld_seams(const Points& points, const Triangles& triangles);

} // namespace geofilter
