#include "feature_source.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace geofilter::cli {

namespace {

template <class Inside>
std::vector<int> faces_inside(const Points& points, const Triangles& triangles, Inside inside) {
    std::vector<int> faces;
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        bool all = true;
        for (int k = 0; k < 3 && all; ++k) all = inside(points.row(triangles(f, k)).transpose());
        if (all) faces.push_back(int(f));
    }
    return faces;
}

std::string describe_box(const Points& points) {
    if (points.rows() == 0) return "the mesh has no vertices";
    const Eigen::RowVector3d lo = points.colwise().minCoeff(), hi = points.colwise().maxCoeff();
    return "the mesh spans (" + format_number(lo[0]) + ", " + format_number(lo[1]) + ", " + format_number(lo[2]) + ") to (" + format_number(hi[0]) + ", " +
           format_number(hi[1]) + ", " + format_number(hi[2]) + ")";
}

} // namespace

std::vector<int> select_points(const Points& points, const CliOptions& options, std::vector<std::string>& log) {
    std::vector<int> selected;
    const auto take = [&](const std::string& what, const auto& inside) {
        size_t found = 0;
        for (Eigen::Index i = 0; i < points.rows(); ++i)
            if (inside(Eigen::Vector3d(points.row(i).transpose()))) {
                selected.push_back(int(i));
                ++found;
            }
        if (found == 0) throw Error(what + " holds no point of the cloud: " + describe_box(points));
        log.push_back(what + ": " + std::to_string(found) + " points");
    };
    for (const auto& s : options.spheres)
        take("--select-sphere " + format_number(s.center[0]) + "," + format_number(s.center[1]) + "," + format_number(s.center[2]) + "," + format_number(s.radius),
             [&](const Eigen::Vector3d& p) { return (p - s.center).squaredNorm() <= s.radius * s.radius; });
    for (const auto& b : options.boxes)
        take("--select-box " + format_number(b.low[0]) + "," + format_number(b.low[1]) + "," + format_number(b.low[2]) + "," + format_number(b.high[0]) + "," +
                 format_number(b.high[1]) + "," + format_number(b.high[2]),
             [&](const Eigen::Vector3d& p) {
                 return (p.array() >= b.low.array()).all() && (p.array() <= b.high.array()).all();
             });
    std::sort(selected.begin(), selected.end());
    selected.erase(std::unique(selected.begin(), selected.end()), selected.end());
    return selected;
}

std::vector<int> select_faces(const Points& points, const Triangles& triangles, const CliOptions& options,
                              const std::vector<int>& stored, std::vector<std::string>& log) {
    std::vector<int> selected = stored;
    if (options.select_stored) log.push_back("--select-stored: " + std::to_string(stored.size()) + " faces");
    for (const auto& s : options.spheres) {
        const auto faces = faces_inside(points, triangles, [&](const Eigen::Vector3d& p) {
            return (p - s.center).squaredNorm() <= s.radius * s.radius;
        });
        const std::string what = "--select-sphere " + format_number(s.center[0]) + "," + format_number(s.center[1]) + "," + format_number(s.center[2]) +
                                 "," + format_number(s.radius);
        if (faces.empty()) throw Error(what + " holds no face with all three vertices inside: " + describe_box(points));
        log.push_back(what + ": " + std::to_string(faces.size()) + " faces");
        selected.insert(selected.end(), faces.begin(), faces.end());
    }
    for (const auto& b : options.boxes) {
        const auto faces = faces_inside(points, triangles, [&](const Eigen::Vector3d& p) {
            return (p.array() >= b.low.array()).all() && (p.array() <= b.high.array()).all();
        });
        const std::string what = "--select-box " + format_number(b.low[0]) + "," + format_number(b.low[1]) + "," + format_number(b.low[2]) + "," +
                                 format_number(b.high[0]) + "," + format_number(b.high[1]) + "," + format_number(b.high[2]);
        if (faces.empty()) throw Error(what + " holds no face with all three vertices inside: " + describe_box(points));
        log.push_back(what + ": " + std::to_string(faces.size()) + " faces");
        selected.insert(selected.end(), faces.begin(), faces.end());
    }
    std::sort(selected.begin(), selected.end());
    selected.erase(std::unique(selected.begin(), selected.end()), selected.end());
    return selected;
}

} // namespace geofilter::cli
