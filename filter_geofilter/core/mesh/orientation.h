// Faces turned to agree with their neighbours. A closed surface encloses a volume and has an
// outside only when every edge is crossed one way by one of its faces and the other way by
// the other; meshes merged from pieces or read from triangle soups often hold faces wound
// the other way, and then the vertex normals cancel where the windings meet.
#pragma once

#include "core/types.h"

namespace geofilter {

struct ConsistentOrientation {
    Triangles triangles;     // the faces, those turned with two corners swapped
    int turned = 0;          // faces turned
    int non_orientable = 0;  // patches left as they were: no winding agrees across all their edges (a Moebius strip)
};

// Faces joined across an edge that has exactly two faces belong to one patch; an edge with
// one face (a boundary) or more than two (non-manifold) joins nothing. In each patch the
// winding that most of its faces already have is kept and the others are turned to it. Faces
// with an index out of range, or with a repeated corner, are left as they are and join nothing.
ConsistentOrientation orient_consistently(const Triangles& triangles, Eigen::Index vertex_count);

} // namespace geofilter
