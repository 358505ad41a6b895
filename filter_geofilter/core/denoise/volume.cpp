#include "core/denoise/volume.h"
#include "core/mesh/components.h"
#include "core/mesh/surface_measures.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace geofilter {

namespace {

// The faces of each component, and whether it is closed (closed_components).
struct ComponentFaces {
    std::vector<std::vector<Eigen::Index>> faces;
    std::vector<bool> closed;
};

ComponentFaces faces_by_component(const Triangles& triangles, const std::vector<int>& component, int count) {
    ComponentFaces out{std::vector<std::vector<Eigen::Index>>(count), closed_components(triangles, component, count)};
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) out.faces[component[triangles(f, 0)]].push_back(f);
    return out;
}

// Summed about one of the component's own vertices, not the origin: a closed surface encloses
// the same volume about any point, and a scan placed far from the origin (world or scanner
// coordinates) otherwise sums terms of its distance cubed that cancel to its volume: a bunny
// 16000 of its sizes away lost its volume to rounding and was moved by 1 % of its size.
double volume_of(const Points& p, const Triangles& t, const std::vector<Eigen::Index>& faces) {
    if (faces.empty()) return 0;
    const Eigen::RowVector3d o = p.row(t(faces.front(), 0));
    double v = 0;
    for (Eigen::Index f : faces) v += (p.row(t(f, 0)) - o).dot((p.row(t(f, 1)) - o).cross(p.row(t(f, 2)) - o)) / 6;
    return v;
}

double area_of(const Points& p, const Triangles& t, const std::vector<Eigen::Index>& faces) {
    double a = 0;
    for (Eigen::Index f : faces) a += face_area(p, t, f);
    return a;
}

} // namespace

Points restore_volume(const Points& input, const Points& smoothed, const Triangles& triangles,
                      VolumeRestoreReport* report) {
    const std::vector<int> component = connected_components(triangles, smoothed.rows());
    const int count = component_count(component);
    const ComponentFaces parts = faces_by_component(triangles, component, count);
    const Eigen::MatrixXd normal = vertex_normals(smoothed, triangles);
    std::vector<std::vector<Eigen::Index>> vertices_of(count);
    for (Eigen::Index v = 0; v < smoothed.rows(); ++v)
        if (normal.row(v).squaredNorm() > 0) vertices_of[component[v]].push_back(v);
    VolumeRestoreReport r;
    Points out = smoothed;
    for (int c = 0; c < count; ++c) {
        if (!parts.closed[c] || parts.faces[c].empty()) continue;
        const double target = volume_of(input, triangles, parts.faces[c]);
        const double area = area_of(smoothed, triangles, parts.faces[c]);
        if (!(std::abs(target) > 0) || !(area > 0)) continue;
        // V(t) is a cubic in the offset t: secant steps from the first-order guess
        // (the volume grows by the area per unit of offset) converge in a few steps.
        const std::vector<Eigen::Index>& vertices = vertices_of[c];
        const auto volume_at = [&](double t) {
            for (Eigen::Index v : vertices) out.row(v) = smoothed.row(v) + t * normal.row(v);
            return volume_of(out, triangles, parts.faces[c]);
        };
        double t0 = 0, v0 = volume_of(smoothed, triangles, parts.faces[c]);
        r.largest_change = std::max(r.largest_change, std::abs(v0 - target) / std::abs(target));
        double t = (target - v0) / area, v1 = volume_at(t);
        for (int step = 0; step < 30 && v1 != v0 && std::abs(v1 - target) > 1e-13 * std::abs(target); ++step) {
            const double next = t + (target - v1) * (t - t0) / (v1 - v0);
            t0 = t;
            v0 = v1;
            t = next;
            v1 = volume_at(t);
        }
        ++r.closed_components;
        r.largest_offset = std::max(r.largest_offset, std::abs(t));
    }
    if (report) *report = r;
    return out;
}

} // namespace geofilter
