#include "core/denoise/normal_motion.h"
#include "core/mesh/components.h"
#include "core/mesh/surface_measures.h"

#include <cmath>
#include <vector>

namespace geofilter {

Points keep_normal_motion(const Points& input, const Points& smoothed, const Triangles& triangles,
                          double max_turn_degrees, NormalMotionReport* report) {
    const Eigen::MatrixXd normals = vertex_normals(smoothed, triangles);
    Points out = smoothed;
    std::vector<bool> projected(static_cast<std::size_t>(input.rows()), false);
    NormalMotionReport r;
    for (Eigen::Index v = 0; v < input.rows(); ++v) {
        const Eigen::RowVector3d n = normals.row(v);
        if (n.squaredNorm() == 0) continue;
        out.row(v) = input.row(v) + (smoothed.row(v) - input.row(v)).dot(n) * n;
        projected[static_cast<std::size_t>(v)] = true;
    }

    const double min_cos = std::cos(max_turn_degrees * 3.14159265358979323846 / 180);
    std::vector<Eigen::Vector3d> reference(static_cast<std::size_t>(triangles.rows()));
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) reference[static_cast<std::size_t>(f)] = twice_area_normal(smoothed, triangles, f);
    // A face of which every vertex is back at the smoother's position equals its reference,
    // so each round either sends a vertex back for good or ends: at most one round per vertex.
    // Only a face with a vertex sent back in the last round can have turned since: the first
    // round checks every face, the next ones only those (the faces of each vertex, once).
    VertexFaces around;  // made once the first round finds a vertex to send back
    std::vector<Eigen::Index> to_check(static_cast<std::size_t>(triangles.rows()));
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) to_check[static_cast<std::size_t>(f)] = f;
    std::vector<Eigen::Index> checked_in_round(static_cast<std::size_t>(triangles.rows()), -1);
    for (bool turned = max_turn_degrees < 180; turned;) {
        turned = false;
        ++r.rounds;
        std::vector<Eigen::Index> back;
        for (Eigen::Index f : to_check) {
            const Eigen::Vector3d& before = reference[static_cast<std::size_t>(f)];
            const Eigen::Vector3d after = twice_area_normal(out, triangles, f);
            const double scale = before.norm() * after.norm();
            if (scale == 0 || after.dot(before) >= min_cos * scale) continue;
            for (int k = 0; k < 3; ++k)
                if (projected[static_cast<std::size_t>(triangles(f, k))]) back.push_back(triangles(f, k));
        }
        if (back.empty()) break;
        if (around.start.empty()) around = vertex_faces(triangles, input.rows());
        to_check.clear();
        for (Eigen::Index v : back) {
            if (!projected[static_cast<std::size_t>(v)]) continue;
            projected[static_cast<std::size_t>(v)] = false;
            out.row(v) = smoothed.row(v);
            turned = true;
            for (int j = around.start[static_cast<std::size_t>(v)]; j < around.start[static_cast<std::size_t>(v) + 1]; ++j) {
                const int f = around.face[static_cast<std::size_t>(j)];
                if (checked_in_round[static_cast<std::size_t>(f)] == r.rounds) continue;
                checked_in_round[static_cast<std::size_t>(f)] = r.rounds;
                to_check.push_back(f);
            }
        }
    }
    for (bool p : projected) (p ? r.vertices_projected : r.vertices_kept_smoothed) += 1;
    if (report) *report = r;
    return out;
}

} // namespace geofilter
