// Connected components of a triangle mesh: a filter acts on each one as its own surface.
#pragma once

#include "core/types.h"

#include <vector>

namespace geofilter {

// Component label (0, 1, ...) of every vertex, vertices joined by shared faces. A vertex in
// no face is a component of its own. Labels are numbered in order of first appearance.
std::vector<int> connected_components(const Triangles& triangles, Eigen::Index vertex_count);

// The same for a symmetric matrix's sparsity pattern (stored entries couple their row and
// column, whatever their value): the components of a Laplacian's vertices.
std::vector<int> connected_components(const SparseMatrix& coupling);

// Each vertex's neighbours through face edges, each once and in increasing order, as
// compressed rows: the neighbours of v are index[start[v] .. start[v+1]).
struct VertexNeighbours {
    std::vector<int> start, index;
};
VertexNeighbours vertex_neighbours(const Triangles& triangles, Eigen::Index vertex_count);

// The faces around each vertex, in increasing face order, as compressed rows: the faces of
// v are face[start[v] .. start[v+1]). Faces listed in skip_face (if non-empty) are left out.
struct VertexFaces {
    std::vector<int> start, face;
};
VertexFaces vertex_faces(const Triangles& triangles, Eigen::Index vertex_count, const std::vector<bool>& skip_face = {});

// The faces sharing at least one vertex with each face, itself included, once each: face f's
// are face[start[f]] .. face[start[f + 1] - 1].
struct FaceNeighbourhoods {
    std::vector<int> start, face;
};
FaceNeighbourhoods faces_sharing_a_vertex(const Triangles& triangles, Eigen::Index vertex_count);

// How many labels `labels` uses.
int component_count(const std::vector<int>& labels);

// Whether each of the `count` components (labels from connected_components) is closed:
// every edge of its faces used exactly once in each direction (two consistently oriented
// faces), so that it encloses a volume. A component without faces is not closed.
std::vector<bool> closed_components(const Triangles& triangles, const std::vector<int>& component, int count);

} // namespace geofilter
