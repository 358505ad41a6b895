#include "run_region.h"

#include <algorithm>
#include <cmath>

namespace geofilter {

namespace {

std::vector<double> weight_from_quality(const RunInput& input, std::vector<std::string>& log) {
    if (!input.vertex_quality || input.vertex_quality->empty())
        throw Error("region = quality needs a per-vertex quality and the mesh has none: compute or paint one first"
                    " (e.g. MeshLab's Colorize by geodesic distance, or Per Vertex Quality Function), or choose another"
                    " region");
    const std::vector<double>& q = *input.vertex_quality;
    if (static_cast<Eigen::Index>(q.size()) != input.points.rows())
        throw Error("internal: " + std::to_string(q.size()) + " vertex qualities for " +
                    std::to_string(input.points.rows()) + " vertices");
    std::vector<double> w(q.size());
    int clamped = 0;
    double low = 0, high = 1;
    for (size_t i = 0; i < q.size(); ++i) {
        if (std::isnan(q[i]))
            throw Error("the quality of vertex " + std::to_string(i) + " is NaN: region = quality takes it as a weight"
                        " in [0, 1]; fix the quality first");
        low = std::min(low, q[i]);
        high = std::max(high, q[i]);
        w[i] = std::clamp(q[i], 0.0, 1.0);
        if (w[i] != q[i]) ++clamped;
    }
    if (clamped > 0)
        log.push_back("warning: " + std::to_string(clamped) + " vertex qualities outside [0, 1] (from " + format_number(low) +
                      " to " + format_number(high) + ") clamped to [0, 1]");
    return w;
}

} // namespace

std::vector<double> region_weight_from_values(int region, double blend_width, const RunInput& input,
                                              const AutoBlendWidth& auto_width, std::vector<std::string>& log) {
    if (region != 1) {
        std::vector<double> weight = weight_from_quality(input, log);
        log.push_back("region: the vertex quality as the weight (blendWidth is not used: the weight is the blend)");
        return weight;
    }
    if (input.selected_faces.empty())
        throw Error("region = selected faces but no faces are selected: select the region first (e.g. with the"
                    " selection tools or Conditional Face Selection), or choose region = whole mesh");
    if (!std::isfinite(blend_width) || blend_width < 0)
        throw Error("blendWidth must be a finite number >= 0 (got " + format_number(blend_width) + "); 0 = auto");
    std::string how = "as given";
    if (blend_width == 0) {
        const auto [width, chosen] = auto_width();
        if (!(width > 0))
            throw Error("blendWidth = 0 (auto) needs the feature frequency, and none is set: give blendWidth");
        blend_width = width;
        how = "auto: " + chosen;
    }
    std::vector<double> weight = region_weight(input.points, input.triangles, input.selected_faces, blend_width);
    log.push_back("region: the " + std::to_string(input.selected_faces.size()) +
                  " selected faces, fading to untouched across a band of width " + format_number(blend_width) + " (" + how + ")");
    return weight;
}

Points filter_region(int region, double blend_width, const RunInput& input, const TransferFunction& g,
                     const FilterOptions& options, double s_feature, FeatureShape shape, FilterReport& report,
                     std::vector<std::string>& log) {
    const bool sphere = shape == FeatureShape::Sphere;
    const std::vector<double> weight = region_weight_from_values(region, blend_width, input, [&] {
        return std::make_pair(s_feature > 0 ? std::sqrt((sphere ? 2.0 : 1.0) / s_feature) : 0.0,
                              "the feature radius at s = " + format_number(s_feature) + (sphere ? ", sqrt(2/s)" : ", sqrt(1/s)"));
    }, log);
    RegionReport r;
    Points out = apply_filter_weighted(input.points, input.triangles, g, weight, options, &report, &r, input.cache);
    const auto untouched = input.points.rows() - r.domain_vertices;
    log.push_back("region: " + std::to_string(r.domain_vertices) + " vertices with weight > 0 filtered as one domain, " +
                  std::to_string(r.ring_vertices) + " around them held fixed (" + std::to_string(r.submesh_vertices) +
                  " solved on); " + std::to_string(untouched) + " vertices left exactly as they were" +
                  (r.free_components > 0 ? "; " + std::to_string(r.free_components) +
                                               " part(s) of the region are whole connected components: filtered alone"
                                         : std::string()));
    return out;
}

} // namespace geofilter
