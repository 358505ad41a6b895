#include "core/denoise/normal_fit.h"
#include "core/mesh/components.h"

#include <cmath>
#include <vector>

namespace geofilter {

Points fit_to_filtered_normals(const Points& points, const Triangles& triangles, NormalFitStrength strength,
                               const Eigen::Vector3d* along) {
    const Eigen::Index faces = triangles.rows();
    const VertexFaces around = vertex_faces(triangles, points.rows());
    Eigen::MatrixXd normal(faces, 3);
    Eigen::VectorXd area(faces);
    for (Eigen::Index f = 0; f < faces; ++f) {
        const Eigen::RowVector3d a = points.row(triangles(f, 0));
        const Eigen::RowVector3d n = (points.row(triangles(f, 1)) - a).cross(points.row(triangles(f, 2)) - a);
        const double length = n.norm();
        area[f] = 0.5 * length;
        normal.row(f) = length > 0 ? Eigen::RowVector3d(n / length) : Eigen::RowVector3d::Zero();
    }
    // The faces sharing a vertex with each face, once each.
    std::vector<int> start(static_cast<std::size_t>(faces) + 1, 0), neighbour;
    {
        std::vector<int> seen(static_cast<std::size_t>(faces), -1);
        for (Eigen::Index f = 0; f < faces; ++f) {
            for (int k = 0; k < 3; ++k) {
                const int v = triangles(f, k);
                for (int i = around.start[static_cast<std::size_t>(v)]; i < around.start[static_cast<std::size_t>(v) + 1]; ++i) {
                    const int g = around.face[static_cast<std::size_t>(i)];
                    if (seen[static_cast<std::size_t>(g)] == f) continue;
                    seen[static_cast<std::size_t>(g)] = static_cast<int>(f);
                    neighbour.push_back(g);
                }
            }
            start[static_cast<std::size_t>(f) + 1] = static_cast<int>(neighbour.size());
        }
    }
    const double width = 1 - std::cos(normal_fit_angle_degrees * M_PI / 180);
    Eigen::MatrixXd smoothed(faces, 3);
    for (int round = 0; round < strength.normal_rounds; ++round) {
        for (Eigen::Index f = 0; f < faces; ++f) {
            Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
            const Eigen::RowVector3d n = normal.row(f);
            for (int i = start[static_cast<std::size_t>(f)]; i < start[static_cast<std::size_t>(f) + 1]; ++i) {
                const int g = neighbour[static_cast<std::size_t>(i)];
                const double apart = (1 - n.dot(normal.row(g))) / width;
                sum += area[g] * std::exp(-apart * apart) * normal.row(g);
            }
            const double length = sum.norm();
            smoothed.row(f) = length > 0 ? Eigen::RowVector3d(sum / length) : n;
        }
        normal.swap(smoothed);
    }
    Points out = points;
    Points step(points.rows(), 3);
    for (int round = 0; round < strength.vertex_rounds; ++round) {
        step.setZero();
        Eigen::VectorXd count = Eigen::VectorXd::Zero(points.rows());
        for (Eigen::Index f = 0; f < faces; ++f) {
            const Eigen::RowVector3d n = normal.row(f);
            if (n.squaredNorm() == 0) continue;
            const Eigen::RowVector3d centroid =
                (out.row(triangles(f, 0)) + out.row(triangles(f, 1)) + out.row(triangles(f, 2))) / 3;
            for (int k = 0; k < 3; ++k) {
                const int v = triangles(f, k);
                step.row(v) += n.dot(centroid - out.row(v)) * n;
                count[v] += 1;
            }
        }
        if (along) step = (step * *along) * along->transpose();
        for (Eigen::Index v = 0; v < points.rows(); ++v)
            if (count[v] > 0) out.row(v) += step.row(v) / count[v];
    }
    // A thin face can be stepped over; its vertices go back to where they were, until no
    // face of the fit is turned over against the same face before it.
    const auto turned = [&](Eigen::Index f) {
        const auto face_normal = [&](const Points& p) {
            const Eigen::RowVector3d a = p.row(triangles(f, 0));
            return Eigen::RowVector3d((p.row(triangles(f, 1)) - a).cross(p.row(triangles(f, 2)) - a));
        };
        return face_normal(out).dot(face_normal(points)) < 0;
    };
    for (bool reverted = true; reverted;) {
        reverted = false;
        for (Eigen::Index f = 0; f < faces; ++f)
            if (turned(f))
                for (int k = 0; k < 3; ++k) {
                    out.row(triangles(f, k)) = points.row(triangles(f, k));
                    reverted = true;
                }
    }
    return out;
}

} // namespace geofilter
