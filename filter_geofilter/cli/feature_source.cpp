#include "feature_source.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace geofilter::cli {

namespace {

std::string num(double v) { return format_number(v); }

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
    return "the mesh spans (" + num(lo[0]) + ", " + num(lo[1]) + ", " + num(lo[2]) + ") to (" + num(hi[0]) + ", " +
           num(hi[1]) + ", " + num(hi[2]) + ")";
}

} // namespace

double apply_feature_radius(const FilterSpec& spec, ParameterValues& values, double radius, std::vector<std::string>& log) {
    const bool cylinder = values.at(param::feature_shape) == 1;
    const double frequency = (cylinder ? 1.0 : 2.0) / (radius * radius);
    const std::string how = std::string(cylinder ? "cylinder-like, s = 1/r^2" : "sphere-like, s = 2/r^2") +
                            " with r = " + num(radius);
    if (spec.kind == FilterKind::SecondOrder) {
        const double s1 = values.at(param::s1), s2 = values.at(param::s2);
        if (!(s1 > 0) || !std::isfinite(s2 / s1))
            throw Error("s1 must be > 0 (got " + num(s1) + "): with --radius it sets the ratio s2/s1");
        values[param::s1] = frequency;
        values[param::s2] = frequency * (s2 / s1);
        log.push_back("s1 = " + num(frequency) + " from --radius (" + how + "); s2 = " + num(frequency * (s2 / s1)) +
                      " keeps s2/s1 = " + num(s2 / s1) + " (given s1 = " + num(s1) + ", s2 = " + num(s2) + ")");
        return frequency;
    }
    if (spec.kind == FilterKind::PoleZero) {
        // featureCorner indexes z1..z4 then p1..p4, as run_filter reads it.
        std::vector<std::string> corners;
        for (const auto& prefix : {param::zero_prefix, param::pole_prefix})
            for (int i = 1; i <= param::max_pole_zero; ++i) corners.push_back(prefix + std::to_string(i));
        const auto corner = size_t(values.at(param::feature_corner));
        if (corner >= corners.size()) throw Error("featureCorner must be an index from 0 to " + std::to_string(corners.size() - 1));
        const std::string& corner_name = corners[corner];
        const double given = values.at(corner_name);
        if (!(given > 0))
            throw Error("featureCorner " + corner_name + " is not in use (0): give it a value, its ratio to the other"
                        " corners is kept");
        const double scale = frequency / given;
        for (const auto& name : corners) values[name] *= scale;
        log.push_back("corner " + corner_name + " = " + num(frequency) + " from --radius (" + how +
                      "); all corners scaled by " + num(scale));
        return frequency;
    }
    if (spec.kind == FilterKind::Butterworth) {
        values[param::cutoff] = frequency;
        log.push_back("cutoff sc = " + num(frequency) + " from --radius (" + how + ")");
        return frequency;
    }
    throw Error("--radius does not apply to " + spec.cli_name +
                (spec.kind == FilterKind::Denoise ? ": select one bump with --select-* instead" : ""));
}

std::vector<int> select_faces(const Points& points, const Triangles& triangles, const CliOptions& options,
                              const std::vector<int>& stored, std::vector<std::string>& log) {
    std::vector<int> selected = stored;
    if (options.select_stored) log.push_back("--select-stored: " + std::to_string(stored.size()) + " faces");
    for (const auto& s : options.spheres) {
        const auto faces = faces_inside(points, triangles, [&](const Eigen::Vector3d& p) {
            return (p - s.center).squaredNorm() <= s.radius * s.radius;
        });
        const std::string what = "--select-sphere " + num(s.center[0]) + "," + num(s.center[1]) + "," + num(s.center[2]) +
                                 "," + num(s.radius);
        if (faces.empty()) throw Error(what + " holds no face with all three vertices inside: " + describe_box(points));
        log.push_back(what + ": " + std::to_string(faces.size()) + " faces");
        selected.insert(selected.end(), faces.begin(), faces.end());
    }
    for (const auto& b : options.boxes) {
        const auto faces = faces_inside(points, triangles, [&](const Eigen::Vector3d& p) {
            return (p.array() >= b.low.array()).all() && (p.array() <= b.high.array()).all();
        });
        const std::string what = "--select-box " + num(b.low[0]) + "," + num(b.low[1]) + "," + num(b.low[2]) + "," +
                                 num(b.high[0]) + "," + num(b.high[1]) + "," + num(b.high[2]);
        if (faces.empty()) throw Error(what + " holds no face with all three vertices inside: " + describe_box(points));
        log.push_back(what + ": " + std::to_string(faces.size()) + " faces");
        selected.insert(selected.end(), faces.begin(), faces.end());
    }
    std::sort(selected.begin(), selected.end());
    selected.erase(std::unique(selected.begin(), selected.end()), selected.end());
    return selected;
}

} // namespace geofilter::cli
