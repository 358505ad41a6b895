// Simple measures of a triangle mesh's surface.
#pragma once

#include "core/types.h"

namespace geofilter {

// Unit normals at the vertices, each the area-weighted mean of its faces' normals; a vertex
// in no face (or only in faces of zero area) gets a zero row.
Eigen::MatrixXd vertex_normals(const Points& points, const Triangles& triangles);

// The area each vertex stands for: a third of the area of each face around it (the lumped
// mass of cotan_laplacian); 0 for a vertex in no face.
Eigen::VectorXd vertex_areas(const Points& points, const Triangles& triangles);

// Mean length of the faces' edges (an edge shared by two faces counts twice); 0 without faces.
double mean_edge_length(const Points& points, const Triangles& triangles);

} // namespace geofilter
