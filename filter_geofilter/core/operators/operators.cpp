#include "core/operators/operators.h"

#include "core/operators/intrinsic_delaunay.h"
#include "core/mesh/components.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace geofilter {

bool operator_uses_positions(Operator op) { return op != Operator::Umbrella; }

const char* operator_name(Operator op) {
    switch (op) {
    case Operator::Cotangent: return "cotangent";
    case Operator::IntrinsicDelaunay: return "intrinsic Delaunay cotangent";
    case Operator::Umbrella: return "umbrella (graph, per-vertex frequency)";
    }
    return "?";
}

Laplacian umbrella_laplacian(const Triangles& triangles, Eigen::Index vertex_count) {
    // Column by column from the sorted neighbour lists, straight into compressed storage:
    // Denoise builds this operator several times on a large mesh, and on a grid of 384k
    // vertices sorting every face's edges and summing triplets took 1.0 s, this 0.3 s.
    const VertexNeighbours nb = vertex_neighbours(triangles, vertex_count);
    Laplacian result;
    result.mass = Eigen::VectorXd::Zero(vertex_count);
    result.stiffness.resize(vertex_count, vertex_count);
    result.stiffness.resizeNonZeros(static_cast<Eigen::Index>(nb.index.size()) + vertex_count);
    int* column_start = result.stiffness.outerIndexPtr();
    int* row = result.stiffness.innerIndexPtr();
    double* value = result.stiffness.valuePtr();
    int k = 0;
    for (Eigen::Index v = 0; v < vertex_count; ++v) {
        column_start[v] = k;
        int diagonal = -1;
        for (int j = nb.start[v]; j < nb.start[v + 1]; ++j) {
            const int w = nb.index[j];
            if (w == v) continue;  // a face with a repeated corner: no edge from a vertex to itself
            if (w > v && diagonal < 0) {
                diagonal = k;
                row[k++] = static_cast<int>(v);
            }
            row[k] = w;
            value[k++] = -1.0;
            result.mass[v] += 1;
        }
        if (nb.start[v + 1] == nb.start[v]) continue;  // in no face: no entry, as no edge names it
        if (diagonal < 0) {
            diagonal = k;
            row[k++] = static_cast<int>(v);
        }
        value[diagonal] = result.mass[v];
    }
    column_start[vertex_count] = k;
    result.stiffness.resizeNonZeros(k);
    return result;
}

Laplacian build_laplacian(Operator op, const Points& points, const Triangles& triangles) {
    switch (op) {
    case Operator::IntrinsicDelaunay: return intrinsic_delaunay_laplacian(points, triangles);
    case Operator::Umbrella: return umbrella_laplacian(triangles, points.rows());
    case Operator::Cotangent: break;
    }
    return cotan_laplacian(points, triangles);
}

} // namespace geofilter
