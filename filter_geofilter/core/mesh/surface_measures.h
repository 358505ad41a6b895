// Simple measures of a triangle mesh's surface.
#pragma once

#include "core/types.h"

namespace geofilter {

// A face's normal scaled by twice its area, right-handed in the order of its corners: half its
// length is the face's area, and summed over a vertex's faces it weights each by its area.
inline Eigen::Vector3d twice_area_normal(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    return (b - a).cross(c - a);
}
inline Eigen::Vector3d twice_area_normal(const Points& points, const Triangles& triangles, Eigen::Index f) {
    return twice_area_normal(points.row(triangles(f, 0)).transpose(), points.row(triangles(f, 1)).transpose(),
                             points.row(triangles(f, 2)).transpose());
}
inline double face_area(const Points& points, const Triangles& triangles, Eigen::Index f) {
    return 0.5 * twice_area_normal(points, triangles, f).norm();
}

// Unit normals at the vertices, each the area-weighted mean of its faces' normals; a vertex
// in no face (or only in faces of zero area) gets a zero row.
Eigen::MatrixXd vertex_normals(const Points& points, const Triangles& triangles);

// The area each vertex stands for: a third of the area of each face around it (the lumped
// mass of cotan_laplacian); 0 for a vertex in no face.
Eigen::VectorXd vertex_areas(const Points& points, const Triangles& triangles);

// Mean length of the faces' edges (an edge shared by two faces counts twice); 0 without faces.
double mean_edge_length(const Points& points, const Triangles& triangles);

} // namespace geofilter
