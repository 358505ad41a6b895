#include "core/denoise/normal_fit.h"
#include "core/mesh/surface_measures.h"

#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

namespace geofilter {

Points fit_to_filtered_normals(const Points& points, const Triangles& triangles, const FaceNeighbourhoods& neighbourhoods,
                               NormalFitStrength strength, const Eigen::Vector3d* along) {
    const auto face_count = static_cast<std::size_t>(triangles.rows());
    // Positions and normals one row per element, contiguous: the rounds below read each
    // neighbour's three coordinates together (Points is stored by column).
    std::vector<Eigen::Vector3d> at(static_cast<std::size_t>(points.rows()));
    for (Eigen::Index v = 0; v < points.rows(); ++v) at[static_cast<std::size_t>(v)] = points.row(v).transpose();
    const auto corner = [&](std::size_t f, int k) -> Eigen::Vector3d& { return at[static_cast<std::size_t>(triangles(static_cast<Eigen::Index>(f), k))]; };
    const auto face_normal_now = [&](std::size_t f) { return twice_area_normal(corner(f, 0), corner(f, 1), corner(f, 2)); };
    std::vector<Eigen::Vector3d> normal(face_count), smoothed(face_count);
    std::vector<double> area(face_count);
    for (std::size_t f = 0; f < face_count; ++f) {
        const Eigen::Vector3d n = face_normal_now(f);
        const double length = n.norm();
        area[f] = 0.5 * length;
        normal[f] = length > 0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
    }
    const std::vector<Eigen::Vector3d> input_normal = normal;
    const std::vector<int>& start = neighbourhoods.start;
    const std::vector<int>& neighbour = neighbourhoods.face;
    const double width = 1 - std::cos(normal_fit_angle_degrees * M_PI / 180);
    const auto smooth_block = [&](std::size_t first, std::size_t last) {
        for (std::size_t f = first; f < last; ++f) {
            Eigen::Vector3d sum = Eigen::Vector3d::Zero();
            const Eigen::Vector3d& n = normal[f];
            for (int i = start[f]; i < start[f + 1]; ++i) {
                const auto g = static_cast<std::size_t>(neighbour[static_cast<std::size_t>(i)]);
                const double apart = (1 - n.dot(normal[g])) / width;
                sum += area[g] * std::exp(-apart * apart) * normal[g];
            }
            const double length = sum.norm();
            smoothed[f] = length > 0 ? Eigen::Vector3d(sum / length) : n;
        }
    };
    // Each face's smoothed normal depends on the round before only: the faces are split
    // between threads, with the same result.
    const std::size_t threads = std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, 4);
    const std::size_t block = (face_count + threads - 1) / threads;
    for (int round = 0; round < strength.normal_rounds; ++round) {
        std::vector<std::thread> helpers;
        for (std::size_t t = 1; t < threads && t * block < face_count; ++t)
            helpers.emplace_back(smooth_block, t * block, std::min(face_count, (t + 1) * block));
        smooth_block(0, std::min(face_count, block));
        for (std::thread& helper : helpers) helper.join();
        normal.swap(smoothed);
    }
    std::vector<Eigen::Vector3d> step(at.size());
    std::vector<int> count(at.size(), 0);
    for (std::size_t f = 0; f < face_count; ++f)
        if (normal[f].squaredNorm() > 0)
            for (int k = 0; k < 3; ++k) ++count[static_cast<std::size_t>(triangles(static_cast<Eigen::Index>(f), k))];
    for (int round = 0; round < strength.vertex_rounds; ++round) {
        std::fill(step.begin(), step.end(), Eigen::Vector3d::Zero());
        for (std::size_t f = 0; f < face_count; ++f) {
            const Eigen::Vector3d& n = normal[f];
            if (n.squaredNorm() == 0) continue;
            const Eigen::Vector3d centroid = (corner(f, 0) + corner(f, 1) + corner(f, 2)) / 3;
            for (int k = 0; k < 3; ++k)
                step[static_cast<std::size_t>(triangles(static_cast<Eigen::Index>(f), k))] += n.dot(centroid - corner(f, k)) * n;
        }
        for (std::size_t v = 0; v < at.size(); ++v) {
            if (count[v] == 0) continue;
            const Eigen::Vector3d s = along ? Eigen::Vector3d(step[v].dot(*along) * *along) : step[v];
            at[v] += s / count[v];
        }
    }
    // A thin face can be stepped over; its vertices go back to where they were, until no
    // face of the fit is turned over against the same face before it.
    for (bool reverted = true; reverted;) {
        reverted = false;
        for (std::size_t f = 0; f < face_count; ++f) {
            if (face_normal_now(f).dot(input_normal[f]) >= 0) continue;
            for (int k = 0; k < 3; ++k) {
                const Eigen::Index v = triangles(static_cast<Eigen::Index>(f), k);
                corner(f, k) = points.row(v).transpose();
            }
            reverted = true;
        }
    }
    Points out(points.rows(), 3);
    for (Eigen::Index v = 0; v < points.rows(); ++v) out.row(v) = at[static_cast<std::size_t>(v)].transpose();
    return out;
}

} // namespace geofilter
