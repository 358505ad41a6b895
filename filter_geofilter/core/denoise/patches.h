// Parts of a mesh. The bump pattern lowpasses one bump on the part around it (bump_pattern.h);
// Denoise scores its candidate lowpasses on a few patches of a large scan instead of on all of
// it (denoise.h): its score is a mean over vertices, which a sample of the surface estimates.
#pragma once

#include "core/types.h"

#include <vector>

namespace geofilter {

// The part of a mesh on a set of its vertices: those vertices (indices into the mesh, in the
// order given), their positions, and the faces with all three corners among them.
struct Submesh {
    std::vector<int> vertex;
    Points points;
    Triangles triangles;
};
Submesh induced_submesh(const Points& points, const Triangles& triangles, const std::vector<int>& vertices);

// `count` patches of at least `size` vertices each, whole rings of the vertex graph around
// their seeds, the seeds spread over the mesh by farthest-point sampling in rings (the first
// is the first vertex in a face; a component no patch has reached yet is reached next), so
// that the patches visit its different parts. No seed lands on a component with fewer than
// `size` vertices and under 1 % of the vertices in faces (scan debris), unless it is the largest. Together as one submesh (patches that meet
// merge). `counted`, per vertex of that submesh: whether it lies at least `margin` rings
// inside, away from where the patches were cut out of the mesh. A filter run on the submesh
// treats a cut as a free boundary, which the mesh does not have there; the mesh's own
// boundary is no cut. When the patches cover the whole mesh every vertex counts.
struct ScoringPatches {
    Submesh mesh;
    std::vector<bool> counted;
    int patches = 0;
};
ScoringPatches scoring_patches(const Triangles& triangles, const Points& points, int count, int size, int margin);

} // namespace geofilter
