// Fitting the surface to its own face normals, smoothed edge-aware.
#pragma once

#include "core/mesh/components.h"
#include "core/types.h"

namespace geofilter {

// A lowpass of the positions is linear: it rounds a sharp edge as much as it smooths a flat
// face's noise, and where it is cut to keep the edges it leaves the finest band's noise in the
// face normals. Smoothing the face normals with weights that fall off with the angle between
// them (a bilateral filter on normals: Zheng, Fu, Au & Tai 2011) averages the noise out of
// each smooth side while faces across an edge hardly mix; the vertices are then moved so that
// each face stands square to its smoothed normal (Sun, Rosin, Martin & Langbein 2007).
// Denoise scores this on top of the chosen lowpass by the same risk estimate, so it is kept
// only where the estimate says it brings the surface closer to the noise-free one.
//
// The angle at which two faces' weight has fallen to 1/e: faces within it are one smooth
// side, faces beyond it an edge. Chosen on the tuning half of experiments/generalize_denoise
// (docs/denoise.md).
constexpr double normal_fit_angle_degrees = 20.0;

struct NormalFitStrength {
    int normal_rounds = 1;  // passes of the bilateral filter over the face normals
    int vertex_rounds = 5;  // passes moving the vertices square to them
};
// Tried in this order, each only when the one before scored lower than what it was added to.
constexpr NormalFitStrength normal_fit_strengths[] = {{1, 5}, {2, 10}, {3, 10}, {5, 20}};

// `points` moved to fit their own face normals smoothed as above. Each normal round replaces
// every face's unit normal by the mean of the unit normals of the faces sharing a vertex with
// it (itself included), weighted by area and by exp(-((1 - cos angle) / (1 - cos
// normal_fit_angle_degrees))^2). Each vertex round moves every vertex by the mean over its
// faces of n (n . (c - v)), n the face's smoothed normal and c its centroid: the step that
// puts v into the plane through c square to n, averaged. Faces of zero area carry no normal
// and no weight; a vertex in no face stays where it is. A face the fit turns over against
// itself in `points` sends its three vertices back to their place in `points`, until none is.
// With `along` (a unit direction), every vertex round moves the vertices along it only, by
// their step's part along it: for noise along one direction, which left the vertices' place
// across it right.
// `neighbourhoods` is faces_sharing_a_vertex(triangles, points.rows()): made once for the
// several fits Denoise scores on the same mesh.
Points fit_to_filtered_normals(const Points& points, const Triangles& triangles, const FaceNeighbourhoods& neighbourhoods,
                               NormalFitStrength strength, const Eigen::Vector3d* along = nullptr);

} // namespace geofilter
