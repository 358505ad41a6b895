#include "run_filter.h"
#include "core/mesh/seams.h"

#include "core/denoise/bump_pattern.h"
#include "run_region.h"
#include "core/feature/ellipsoid_view.h"
#include "core/feature/icosphere.h"

#include "core/denoise/denoise.h"
#include "core/mesh/mesh_prep.h"
#include "core/mesh/orientation.h"
#include "core/mesh/surface_measures.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace geofilter {

namespace {

double value_of(const FilterSpec& spec, const ParameterValues& values, const std::string& name) {
    auto it = values.find(name);
    if (it != values.end()) return it->second;
    const ParameterSpec* p = spec.parameter(name);
    if (!p) throw Error("internal: filter " + spec.name + " has no parameter " + name);
    if (p->type == ParameterType::Length)
        throw Error(name + " has no value: its default is " + format_number(100 * p->default_value) +
                    " % of the mesh's bounding-box diagonal, and there is no mesh here; give it");
    return p->default_value;
}

// The frequency of a feature of radius r: 2/r^2 sphere-like, 1/r^2 cylinder-like.
double frequency_of_radius(double radius, FeatureShape shape) {
    return (shape == FeatureShape::Sphere ? 2.0 : 1.0) / (radius * radius);
}

// The radius parameter, refused unless it is a usable length.
double typed_radius(const FilterSpec& spec, const ParameterValues& values) {
    const double r = value_of(spec, values, param::radius);
    if (!(r > 0) || !std::isfinite(r))
        throw Error("radius must be a finite length > 0 (got " + format_number(r) + "): the size of the features to filter");
    return r;
}

// An enum parameter's index, refused unless it names one of the choices.
int choice_of(const FilterSpec& spec, const ParameterValues& values, const std::string& name) {
    const double v = value_of(spec, values, name);
    const auto count = static_cast<double>(spec.parameter(name)->choices.size());
    if (!(v >= 0 && v < count && v == std::floor(v)))
        throw Error(name + " must be an index from 0 to " + format_number(count - 1) + " (got " + format_number(v) + ")");
    return static_cast<int>(v);
}

FeatureShape shape_of(const FilterSpec& spec, const ParameterValues& values) {
    return choice_of(spec, values, param::feature_shape) == 1 ? FeatureShape::Cylinder : FeatureShape::Sphere;
}

std::string describe_feature(const FeatureEllipsoid& e) {
    std::ostringstream os;
    os.precision(5);
    os << e.selection_size() << ", area " << e.area << "; ellipsoid radii " << e.radii[0] << ", " << e.radii[1]
       << ", " << e.radii[2] << "; centre (" << e.center[0] << ", " << e.center[1] << ", " << e.center[2]
       << "); axes (" << e.axes(0, 0) << ", " << e.axes(1, 0) << ", " << e.axes(2, 0) << "), (" << e.axes(0, 1) << ", "
       << e.axes(1, 1) << ", " << e.axes(2, 1) << "), (" << e.axes(0, 2) << ", " << e.axes(1, 2) << ", " << e.axes(2, 2)
       << "); feature radius r = " << e.radius << " (the radii pairs blended by roundness)";
    return os.str();
}

int order_of(const FilterSpec& spec, const ParameterValues& values) {
    const double v = value_of(spec, values, param::order);
    if (!(v >= 1 && v <= butterworth_max_order && v == std::floor(v)))
        throw Error("order must be an integer from 1 to " + std::to_string(butterworth_max_order) + " (got " + format_number(v) + ")");
    return static_cast<int>(v);
}

} // namespace

std::optional<Operator> operator_from_values(const FilterSpec& spec, const ParameterValues& values, bool has_feature) {
    if (!spec.parameter(param::laplace_operator)) return Operator::Cotangent;
    switch (choice_of(spec, values, param::laplace_operator)) {
    case 1: return Operator::Cotangent;
    case 2: return Operator::IntrinsicDelaunay;
    case 3: return Operator::Umbrella;
    default: break;
    }
    // Automatic: a bump's size is geometric, so the cotangent operator; for per-vertex noise
    // Denoise tries the umbrella and the intrinsic Delaunay operator on the mesh (denoise.h).
    if (spec.kind == FilterKind::Denoise && !has_feature) return std::nullopt;
    return Operator::Cotangent;
}

ParameterValues default_values(const FilterSpec& spec, bool has_selection, double diagonal) {
    ParameterValues v;
    for (const auto& p : spec.parameters)
        if (p.type != ParameterType::Length) v[p.name] = p.default_value;
    if (spec.parameter(param::use_selection)) v[param::use_selection] = has_selection ? 1 : 0;
    complete_lengths(spec, v, diagonal);
    return v;
}

void complete_lengths(const FilterSpec& spec, ParameterValues& values, double diagonal) {
    if (!std::isfinite(diagonal)) return;
    for (const auto& p : spec.parameters)
        if (p.type == ParameterType::Length && !values.count(p.name)) values[p.name] = p.default_value * diagonal;
}

TransferFunction design_from_values(const FilterSpec& spec, const ParameterValues& values, const FeatureEllipsoid* feature,
                                    std::vector<std::string>& log, double* s1_used, double* s2_used) {
    const FeatureShape shape = shape_of(spec, values);
    const char* shape_name = shape == FeatureShape::Sphere ? "sphere-like, s = 2/r^2" : "cylinder-like, s = 1/r^2";
    if (spec.kind == FilterKind::SecondOrder) {
        SecondOrderSpec s{value_of(spec, values, param::s1), value_of(spec, values, param::s2),
                          value_of(spec, values, param::G0), value_of(spec, values, param::G1),
                          value_of(spec, values, param::Ginf)};
        if (!(s.s1 >= 0) || !(s.s2 >= 0) || !std::isfinite(s.s1) || !std::isfinite(s.s2))
            throw Error("s1 and s2 must be finite frequencies >= 0 (got s1 = " + format_number(s.s1) + ", s2 = " + format_number(s.s2) +
                        "); 0 = from the feature radius");
        if (s.s1 == 0 && s.s2 > 0)
            throw Error("s2 = " + format_number(s.s2) + " is typed but s1 is 0: type s1 too (the frequencies are then used as"
                        " typed), or leave s2 at 0 to design from the feature radius");
        // A size gives s1; the curve keeps its shape: the typed ratio s2/s1, or the preset's.
        const bool typed_ratio = s.s1 > 0 && s.s2 > 0;
        const double ratio = typed_ratio ? s.s2 / s.s1 : spec.reference.s2 / spec.reference.s1;
        const std::string ratio_note = " keeps " + std::string(typed_ratio ? "the typed" : "this filter's") +
                                       " ratio s2/s1 = " + format_number(ratio);
        if (feature) {
            const double measured = feature->frequency(shape);
            log.push_back("s1 = " + format_number(measured) + " from " + feature->selection_size() + " (" +
                          shape_name + ", r = " + format_number(feature->radius) + ")" +
                          (s.s1 > 0 ? ", instead of the typed " + format_number(s.s1) : std::string()) + "; s2 = " +
                          format_number(measured * ratio) + ratio_note +
                          " (turn useSelection off to use the radius or the typed frequencies)");
            s.s1 = measured;
            s.s2 = measured * ratio;
        } else if (s.s1 > 0) {
            if (s.s2 == 0) s.s2 = s.s1 * ratio;
            log.push_back("s1 = " + format_number(s.s1) + ", s2 = " + format_number(s.s2) + (typed_ratio ? " as typed" : " (s1 as typed; s2" + ratio_note + ")") +
                          "; the feature radius is not used");
        } else {
            const double r = typed_radius(spec, values);
            s.s1 = frequency_of_radius(r, shape);
            s.s2 = s.s1 * ratio;
            log.push_back("s1 = " + format_number(s.s1) + " from the feature radius r = " + format_number(r) + " (" + shape_name + "); s2 = " +
                          format_number(s.s2) + ratio_note);
        }
        log.push_back("design: s1 = " + format_number(s.s1) + ", s2 = " + format_number(s.s2) + ", G0 = " + format_number(s.G0) + ", G1 = " + format_number(s.G1) +
                      ", Ginf = " + format_number(s.Ginf));
        if (s1_used) *s1_used = s.s1;
        if (s2_used) *s2_used = s.s2;
        return design_second_order(s);
    }
    if (spec.kind == FilterKind::PoleZero) {
        PoleZeroSpec pz;
        pz.G0 = value_of(spec, values, param::G0);
        std::vector<double> corners;  // z1..z4, p1..p4 as given, 0 = unused
        for (const auto& prefix : {param::zero_prefix, param::pole_prefix})
            for (int i = 1; i <= param::max_pole_zero; ++i) corners.push_back(value_of(spec, values, prefix + std::to_string(i)));
        for (size_t i = 0; i < corners.size(); ++i) {
            const std::string name = (i < param::max_pole_zero ? "z" : "p") + std::to_string(i % param::max_pole_zero + 1);
            if (!std::isfinite(corners[i]) || corners[i] < 0)
                throw Error(name + " must be a finite number >= 0 (got " + format_number(corners[i]) + "); 0 means unused");
        }
        // A size, measured or given, sets the chosen corner; the others keep their ratios to it.
        double sized = 0;
        std::string source;
        if (feature) {
            sized = feature->frequency(shape);
            source = feature->selection_size() + " (" + shape_name + ")";
        } else if (const double r = value_of(spec, values, param::radius); r != 0) {
            if (!(r > 0) || !std::isfinite(r))
                throw Error("radius must be a finite length >= 0 (got " + format_number(r) + "); 0 = the corners as typed");
            sized = frequency_of_radius(r, shape);
            source = "the feature radius r = " + format_number(r) + " (" + shape_name + ")";
        }
        if (sized > 0) {
            const int corner = choice_of(spec, values, param::feature_corner);
            const double typed = corners[corner];
            if (typed == 0)
                throw Error("featureCorner names a corner frequency that is not in use (0): give it a value, its ratio to"
                            " the others is kept");
            const double scale = sized / typed;
            for (double& c : corners) c *= scale;
            log.push_back("corner " + std::string(corner < param::max_pole_zero ? "z" : "p") +
                          std::to_string(corner % param::max_pole_zero + 1) + " = " + format_number(sized) + " from " + source +
                          ", instead of the typed " + format_number(typed) + "; all corners scaled by " + format_number(scale));
            if (s1_used) *s1_used = sized;
        }
        for (int i = 0; i < param::max_pole_zero; ++i) {
            if (corners[i] > 0) pz.zeros.push_back(corners[i]);
            if (corners[param::max_pole_zero + i] > 0) pz.poles.push_back(corners[param::max_pole_zero + i]);
        }
        std::vector<std::string> warnings;
        TransferFunction g = design_pole_zero(pz, &warnings);
        for (auto& w : warnings) log.push_back("warning: " + w);
        return g;
    }
    if (spec.kind == FilterKind::Butterworth) {
        const int order = order_of(spec, values);
        double cutoff = value_of(spec, values, param::cutoff);
        const Operator op = *operator_from_values(spec, values, feature != nullptr);
        if (!(cutoff >= 0) || !std::isfinite(cutoff))
            throw Error("cutoff must be a finite frequency >= 0 (got " + format_number(cutoff) + "); 0 = from the feature radius");
        if (feature) {
            cutoff = feature->frequency(shape);
            log.push_back("cutoff sc = " + format_number(cutoff) + " from the selection (" + shape_name + ", r = " +
                          format_number(feature->radius) + ")");
        } else if (cutoff > 0) {
            log.push_back("cutoff sc = " + format_number(cutoff) + " as typed; the feature radius is not used");
        } else {
            const double r = typed_radius(spec, values);
            cutoff = frequency_of_radius(r, shape);
            log.push_back("cutoff sc = " + format_number(cutoff) + " from the feature radius r = " + format_number(r) + " (" + shape_name + ")");
        }
        TransferFunction g = design_butterworth_lowpass(cutoff, order);
        log.push_back("design: Butterworth lowpass of order " + std::to_string(order) + ", cutoff sc = " + format_number(cutoff) +
                      (op == Operator::Umbrella ? " (per-vertex frequency)" : " (features of radius " +
                                                                                   format_number(std::sqrt(2 / cutoff)) +
                                                                                   " halved, sphere-like)") +
                      ", operator " + operator_name(op));
        if (s1_used) *s1_used = cutoff;
        return g;
    }
    if (spec.kind == FilterKind::Denoise) {
        const int order = order_of(spec, values);
        if (!feature)
            throw Error("Denoise with nothing selected picks its lowpass on the mesh itself (by its estimated risk): there is"
                        " no design before the mesh is seen; select one bump (or give a radius) to design it alone");
        const Operator op = *operator_from_values(spec, values, true);
        const DenoiseDesign d = design_denoise_from_bump(*feature, shape, order, op);
        log.push_back("cutoff sc = " + format_number(d.cutoff) + " from " + d.origin);
        log.push_back("design: Butterworth lowpass of order " + std::to_string(order) + ", cutoff sc = " + format_number(d.cutoff) +
                      ", operator " + operator_name(op));
        if (s1_used) *s1_used = d.cutoff;
        return d.g;
    }
    throw Error("internal: " + spec.name + " is not a filter");
}

FilterOptions filter_options(const FilterSpec& spec, const ParameterValues& values) {
    FilterOptions options;
    options.solver = choice_of(spec, values, param::solver) == 1 ? Solver::JacobiPcg : Solver::Factored;
    options.tolerance = value_of(spec, values, param::tolerance);
    const double cap = value_of(spec, values, param::max_iterations);
    if (!(cap >= 1 && cap <= 1e9)) throw Error("maxIterations must be between 1 and 1e9 (got " + format_number(cap) + ")");
    options.max_iterations = static_cast<int>(cap);
    options.fix_boundary = value_of(spec, values, param::fix_boundary) != 0;
    return options;
}

namespace {

// What the designed G does, from its description to its peak and the warnings about it.
void log_response(const FilterSpec& spec, const ParameterValues& values, RunOutput& out) {
    out.log.push_back(out.transfer.describe());
    const double g1 = spec.kind == FilterKind::SecondOrder ? value_of(spec, values, param::G1) : 0.0;
    const double s_ref = out.s1_used > 0 ? out.s1_used : 1.0;
    const ResponseReport response = analyse_response(out.transfer, g1, s_ref * 1e-4, s_ref * 1e4);
    out.log.push_back("peak |G| = " + format_number(response.peak_gain) + " at s = " + format_number(response.peak_frequency) +
                      "; G(0) = " + format_number(out.transfer(0)) + ", G(inf) = " + format_number(out.transfer.at_infinity()));
    for (const auto& w : response.warnings) out.log.push_back("warning: " + w);
}

} // namespace

namespace {

// The feature radius the design took its frequency from when nothing was measured: 0 where
// the frequencies were typed (s1, cutoff) or the filter has no radius.
double radius_behind_design(const FilterSpec& spec, const ParameterValues& values) {
    if (!spec.parameter(param::radius) || !values.count(param::radius)) return 0;
    switch (spec.kind) {
    case FilterKind::SecondOrder: return value_of(spec, values, param::s1) == 0 ? values.at(param::radius) : 0;
    case FilterKind::Butterworth: return value_of(spec, values, param::cutoff) == 0 ? values.at(param::radius) : 0;
    case FilterKind::PoleZero: return values.at(param::radius);
    default: return 0;
    }
}

} // namespace

RunOutput design_run(const FilterSpec& spec, const ParameterValues& values, const std::optional<FeatureEllipsoid>& feature) {
    RunOutput out;
    out.feature = feature;
    out.radius_used = feature ? feature->radius : radius_behind_design(spec, values);
    if (feature) out.log.push_back("feature: " + describe_feature(*feature));
    out.op = *operator_from_values(spec, values, feature.has_value());
    out.transfer = design_from_values(spec, values, feature ? &*feature : nullptr, out.log, &out.s1_used, &out.s2_used);
    log_response(spec, values, out);
    return out;
}

void log_filter_report(RunOutput& out, const FilterOptions& options) {
    for (const auto& w : out.report.warnings) out.log.push_back("warning: " + w);
    if (out.report.fixed_vertices > 0)
        out.log.push_back(std::to_string(out.report.fixed_vertices) + " boundary vertices kept in place (fixBoundary)");
    const FilterReport& r = out.report;
    const bool krylov = r.krylov_steps > 0;
    out.log.push_back("solver " + solver_used(r) + ": " + std::to_string(r.active_vertices) + " vertices in " +
                      std::to_string(r.components) + " component(s), " +
                      (krylov ? std::string() : std::to_string(r.iterations) + " CG iterations, ") + "accurate to " +
                      format_number(options.tolerance) + " of the bounding-box diagonal (error bound)" +
                      (krylov ? std::string() : ", relative residual " + format_number(r.relative_residual)) + "; time " +
                      format_number(r.seconds_total) + " s (assembly " + format_number(r.seconds_assembly) +
                      (krylov ? std::string() : ", factorisation " + format_number(r.seconds_factorization)) + ", solve " +
                      format_number(r.seconds_solve) + ")");
    if (!r.reused.empty()) out.log.push_back("reused from the previous run on this mesh: " + r.reused);
}

namespace {

// On a cloud the operator is the cloud's own: its fans are a non-manifold soup, which the
// intrinsic Delaunay flips cannot take; the umbrella operator (the fans' graph) still can.
std::optional<Operator> cloud_operator(const FilterSpec& spec, const ParameterValues& values, bool has_feature) {
    const std::optional<Operator> op = operator_from_values(spec, values, has_feature);
    if (op == Operator::IntrinsicDelaunay)
        throw Error("operator = intrinsic Delaunay needs a triangle mesh; a point cloud's Laplacian is built from its"
                    " points (its local Delaunay triangles): choose Automatic or cotangent");
    return op;
}

// The filtering itself, for a mesh or for a cloud's surface (`cloud` set: `input` carries the
// cloud's local triangles and the selected faces derived from its selected points).
RunOutput filter_surface(const FilterSpec& spec, const ParameterValues& given, const RunInput& input,
                         const CloudSurface* cloud) {
    ParameterValues values = given;
    complete_lengths(spec, values, bounding_box_diagonal(input.points));
    const int region = spec.parameter(param::region) ? choice_of(spec, values, param::region) : 0;
    // Denoise on a region designs on the mesh: the selection, if any, is the region, no feature.
    const bool use_selection = spec.kind == FilterKind::Measure ||
                               (value_of(spec, values, param::use_selection) != 0 &&
                                !(spec.kind == FilterKind::Denoise && region != 0));
    std::optional<FeatureEllipsoid> feature;
    if (use_selection && cloud) {
        // The feature is the selected points' own shape; the derived faces (fans inside the
        // selection) would drop the points along its rim.
        if (input.selected_vertices.empty())
            throw Error(spec.kind == FilterKind::Measure
                            ? "no points of the cloud are selected: select the feature's points to measure first"
                            : "useSelection is on but no points of the cloud are selected: select the feature's points"
                              " (e.g. geofilter --select-sphere, or selected_vertices), or turn useSelection off and"
                              " give the radius");
        feature = measure_feature_of_points(input.points, input.selected_vertices, cloud->cloud.laplacian.mass);
    } else if (use_selection) {
        if (input.selected_faces.empty())
            throw Error(spec.kind == FilterKind::Measure
                            ? "no faces are selected: select the feature to measure first"
                            : "useSelection is on but no faces are selected: select the feature (e.g. with the selection"
                              " tools or Conditional Face Selection), or turn useSelection off and give the frequency directly");
        feature = measure_feature(input.points, input.triangles, input.selected_faces);
    }
    if (spec.kind == FilterKind::Measure) {
        RunOutput out;
        out.feature = feature;
        out.log.push_back("feature: " + describe_feature(*feature));
        const FeatureEllipsoid& e = *out.feature;
        out.log.push_back("feature frequency: sphere-like s = 2/r^2 = " + format_number(e.frequency(FeatureShape::Sphere)) +
                          ", cylinder-like s = 1/r^2 = " + format_number(e.frequency(FeatureShape::Cylinder)));
        // Shown a little off the surface and never flat, in colour (the adapters).
        const FeatureEllipsoid shown = shown_ellipsoid(e);
        out.ellipsoid_mesh = ellipsoid_mesh(shown);
        std::ostringstream axes;
        axes.precision(5);
        for (int k = 0; k < 3; ++k)
            axes << (k ? "; " : "") << "(" << e.axes(0, k) << ", " << e.axes(1, k) << ", " << e.axes(2, k) << ") radius "
                 << e.radii[k];
        out.log.push_back("ellipsoid axes (unit directions, measured radii): " + axes.str() +
                          "; the layer draws radii " + format_number(shown.radii[0]) + ", " + format_number(shown.radii[1]) + ", " +
                          format_number(shown.radii[2]) + " (2% larger, at least 5% of the largest) to stand off the surface");
        return out;
    }

    FilterOptions options = filter_options(spec, values);
    if (cloud && options.fix_boundary)
        throw Error("fixBoundary keeps a mesh's open boundary in place; a point cloud has no faces to tell where its"
                    " boundary is: turn fixBoundary off");
    options.progress = input.progress;
    options.external_solver = input.external_solver;
    options.complex_factorization = input.complex_factorization;

    // Denoise designs on the mesh (it tries its candidates there and keeps the best-scoring
    // one, already applied to the whole mesh) unless the selection is one bump to remove: with
    // nothing selected, on a region (the selection, if any, is the region), and when the
    // selection is too large to be one bump of a pattern.
    RunOutput out;
    std::optional<SamplingDenoise> sampled;
    std::string sampling_why;
    if (spec.kind == FilterKind::Denoise) {
        if (region != 0) {
            sampling_why = region == 1 ? "the selection is the region to denoise, not a bump to remove"
                                       : "the vertex quality weighs where to denoise";
        } else if (feature) {
            const double share = selected_area_share(input.points, input.triangles, input.selected_faces);
            if (share >= denoise_largest_bump_share) {
                out.log.push_back("feature: " + describe_feature(*feature));
                sampling_why = "the selection covers " + format_number(100 * share) + " % of the mesh's area, " +
                               format_number(100 * denoise_largest_bump_share) +
                               " % or more: that is no bump of a pattern (a lowpass cut at twice its radius would"
                               " reshape the whole mesh), so per-vertex sampling noise is removed instead";
                feature.reset();
            }
        }
    }
    // Denoise's region, before the denoising: a region it cannot use is refused at once.
    std::optional<std::vector<double>> denoise_weight;
    if (spec.kind == FilterKind::Denoise && region != 0) {
        denoise_weight = region_weight_from_values(region, value_of(spec, values, param::blend_width), input, [&] {
            const PreparedMesh usable = prepare_mesh(input.points, input.triangles);  // refuses bad indices first
            const double h = mean_edge_length(usable.points, usable.triangles);
            return std::make_pair(denoise_blend_edges * h, format_number(denoise_blend_edges) + " mean edge lengths of " + format_number(h) +
                                                               " (Denoise has no feature radius)");
        }, out.log);
    }
    // The sampling-noise rule: the lowpass chosen on the mesh by estimated risk, applied, with
    // the options as the user gave them (the bump path below may hold the boundary).
    const FilterOptions sampling_options = options;
    const auto sampling_surface = [&]() {
        return cloud ? DenoiseSurface{cloud_operator(spec, values, false), true}
                     : DenoiseSurface{operator_from_values(spec, values, false), false};
    };
    const auto fit_rounds = [](const NormalFitStrength& strength) {
        return std::to_string(strength.normal_rounds) + (strength.normal_rounds == 1 ? " round" : " rounds") +
               " over the normals, " + std::to_string(strength.vertex_rounds) + " over the vertices";
    };
    const auto sampling_rule = [&]() {
        out.log.push_back("Denoise: the sampling-noise rule (the lowpass chosen on the mesh by estimated risk)" +
                          (sampling_why.empty() ? std::string(", nothing selected") : ": " + sampling_why));
        const int order = order_of(spec, values);
        sampled = denoise_sampling_noise(input.points, input.triangles, order, sampling_surface(), sampling_options);
        const DenoiseDesign& d = sampled->design;
        out.op = d.op;
        out.transfer = d.g;
        out.s1_used = d.cutoff;
        out.log.push_back(std::string("noise model: ") + noise_model_name(sampled->noise.model) +
                          (cloud ? std::string(" (on a point cloud always: where a point sits along the surface is its sampling,"
                                               " which no smoother can tell from noise)")
                                 : " (tangential / normal part of the umbrella offsets where the mesh is most regular: " +
                                       format_number(sampled->noise.tangential_ratio) +
                                       "; 2 and up: not along the normals; then the offsets' principal direction (" +
                                       format_number(sampled->noise.direction.x(), 3) + ", " +
                                       format_number(sampled->noise.direction.y(), 3) + ", " +
                                       format_number(sampled->noise.direction.z(), 3) + ") holds " +
                                       format_number(100 * sampled->noise.direction_share, 3) + " % of their variance; " +
                                       format_number(100 * noise_direction_share, 3) + " % and up: along that direction, else in every direction" +
                                       (sampled->noise.tangential_ratio_where_noisy > 0
                                            ? "; where the noise is (a variance of at least " + format_number(noisy_vertex_share) +
                                                  " of the mean): " + format_number(sampled->noise.tangential_ratio_where_noisy) +
                                                  "; below 2 there: along the normals"
                                            : std::string()) + ")"));
        const auto scored = std::count_if(sampled->scores.begin(), sampled->scores.end(),
                                          [](const auto& candidate) { return candidate.second.has_value(); });
        const double sigma = std::sqrt(sampled->variance.mean);
        const bool one_direction = sampled->noise.model == NoiseModel::AlongDirection;
        out.log.push_back(std::string(one_direction ? "noise along that direction" : "noise along the normals") +
                          ": standard deviation " + format_number(sigma) + " = " +
                          format_number(sigma / mean_edge_length(input.points, input.triangles)) +
                          " mean edge lengths on average (from what the umbrella lowpass at frequency 1 removes along"
                          " it, per vertex over its " + std::to_string(noise_neighbourhood_vertices) + " nearest" +
                          (one_direction ? std::string(")")
                                         : ", less what the same reads on the mesh smoothed along its normals, the clean mesh's own"
                                           " detail and sampling: " + format_number(std::sqrt(sampled->own_detail_variance)) + ")"));
        if (sampled->impulses > 0)
            out.log.push_back("impulses: " + std::to_string(sampled->impulses) + " vertices stood more than " +
                              format_number(denoise_impulse_sigmas) + " standard deviations of their noise out of the surface,"
                              " and " + format_number(denoise_impulse_alone) +
                              " times farther than any neighbour: put back on the mean of their neighbours first");
        out.log.push_back(std::string("risk estimate ") + (sampling_why.empty() ? "(nothing selected)" : "(on the whole mesh)") +
                          ": " + std::to_string(scored) + " of " +
                          std::to_string(sampled->scores.size()) +
                          " lowpasses scored, each operator's cutoffs searched downhill from the middle one" +
                          (sampled->scoring_patches
                               ? ", on " + std::to_string(sampled->scoring_patches) + " patches of the mesh (a mean over " +
                                     std::to_string(sampled->scored_vertices) + " vertices at least " +
                                     std::to_string(denoise_scoring_margin) + " rings inside them; the mesh has more than " +
                                     std::to_string(denoise_scoring_vertices) + ")"
                               : std::string()) +
                          "; estimated mean squared distance to the noise-free surface x 1e6 (lower is better; residual, "
                          "degrees of freedom / noisy numbers; how the lowpass was applied):");
        for (std::size_t i = 0; i < sampled->scores.size(); ++i) {
            const auto& [candidate, score] = sampled->scores[i];
            const int steps = sampled->krylov_steps[i];
            out.log.push_back("  " + candidate.origin + ": " +
                              (score ? format_number(1e6 * score->risk) + " (" + format_number(1e6 * score->residual) + ", " +
                                           format_number(score->degrees_of_freedom / score->observations) + "; " +
                                           (steps ? std::to_string(steps) + " Lanczos steps" : std::string("by solves")) + ", " +
                                           format_number(sampled->scoring_seconds[i], 2) + " s)"
                                     : std::string("not scored (beyond a higher score)")) +
                              (candidate.origin == d.origin && !sampled->input_kept && !sampled->normal_fit ? "  <- chosen" : ""));
        }
        for (const auto& [strength, score] : sampled->normal_fit_scores) {
            const bool kept = sampled->normal_fit && sampled->normal_fit->normal_rounds == strength.normal_rounds &&
                              sampled->normal_fit->vertex_rounds == strength.vertex_rounds;
            out.log.push_back("  that lowpass, then fitted to its face normals smoothed edge-aware (" + fit_rounds(strength) +
                              "): " + format_number(1e6 * score.risk) +
                              " (" + format_number(1e6 * score.residual) + ", " +
                              format_number(score.degrees_of_freedom / score.observations) + ")" +
                              (kept && !sampled->input_kept ? "  <- chosen" : ""));
        }
        out.log.push_back("  leaving the mesh as it is (the noise's own variance): " + format_number(1e6 * sampled->input_risk) +
                          (sampled->input_kept ? "  <- chosen" : ""));
        const SamplingDenoise::Seconds& t = sampled->seconds;
        out.log.push_back("Denoise's time: " + format_number(sampled->report.seconds_total, 3) + " s (the noise's variance " +
                          format_number(t.variance, 2) + ", its direction " + (sampled->scoring_patches ? "and the patches " : "") +
                          format_number(t.direction, 2) + ", scoring " + format_number(t.scoring, 2) +
                          (sampled->input_kept ? std::string(")") : ", the chosen lowpass and what follows it " + format_number(t.final_run, 2) + ")"));
        if (sampled->input_kept) {
            const std::string why =
                sigma > 0 ? "no lowpass scored below leaving the mesh as it is: the noise (" + format_number(sigma) +
                                " along the normals) is smaller than what the mildest of them would take of the"
                                " surface's own shape, so the mesh was left unchanged"
                          : std::string("no noise was read once the clean mesh's own detail was subtracted, so the mesh was left unchanged");
            out.report.warnings.push_back(why);
        } else {
            out.log.push_back("cutoff sc = " + format_number(d.cutoff) + " from the sampling: " + d.origin);
            out.log.push_back("design: Butterworth lowpass of order " + std::to_string(order) + ", cutoff sc = " +
                              format_number(d.cutoff) + ", operator " + operator_name(d.op));
            log_response(spec, values, out);
            if (const auto& fit = sampled->normal_fit)
                out.log.push_back("then fitted to its face normals smoothed edge-aware (faces more than " +
                                  format_number(normal_fit_angle_degrees) + " degrees apart hardly mix; " + fit_rounds(*fit) +
                                  "): it scored lower than the lowpass alone");
        }
        if (sampled->input_kept) {
            out.points = input.points;
            return;
        }
        out.points = std::move(sampled->points);
        // The run's report is the chosen lowpass's; warnings already given (the bump path's) stay.
        std::vector<std::string> warnings = std::move(out.report.warnings);
        out.report = sampled->report;
        out.report.warnings.insert(out.report.warnings.begin(), warnings.begin(), warnings.end());
        if (const auto& m = sampled->normal_motion)
            out.log.push_back("motion along the normals only (the noise looks along them): " +
                              std::to_string(m->vertices_projected) + " vertices kept the lowpass's motion across the surface and not its sideways drift; " +
                              std::to_string(m->vertices_kept_smoothed) + " kept the lowpass's position (" +
                              (cloud ? std::string("no normal; a cloud's fans fold nothing, so none is checked for turning")
                                     : "a face turned by more than " + format_number(normal_motion_max_turn_degrees) +
                                           " degrees otherwise, or no normal") + ")");
        if (sampled->noise.model == NoiseModel::AlongDirection)
            out.log.push_back("motion along the noise's direction only: each vertex kept the lowpass's motion along it, not across it");
        if (const auto& b = sampled->motion_bound)
            out.log.push_back("motion held within " + format_number(denoise_motion_bound_sigmas) +
                              " standard deviations of the noise (" + format_number(b->bound) + "): " +
                              std::to_string(b->vertices_held) + " vertices would have moved farther");
        const VolumeRestoreReport& v = sampled->volume;
        out.log.push_back(v.closed_components == 0
                              ? std::string("no closed component: the volume was left as the lowpass made it")
                              : "volume kept: " + std::to_string(v.closed_components) +
                                    " closed component(s) moved along their normals by at most " + format_number(v.largest_offset) +
                                    " (the lowpass had changed the volume by up to " + format_number(100 * v.largest_change) + " %)");
    };
    if (spec.kind == FilterKind::Denoise && !feature) {
        sampling_rule();
    } else {
        if (cloud) cloud_operator(spec, values, feature.has_value());  // refuses intrinsic Delaunay
        out = design_run(spec, values, feature);
    }
    options.op = out.op;
    if (sampled) {
        if (denoise_weight && !sampled->input_kept) {
            // The region takes the denoised points by its weight, as the other filters' regions
            // take their filtered points: outside it every vertex stays bit for bit.
            const std::vector<double>& weight = *denoise_weight;
            out.points = blend_by_weight(input.points, out.points, weight);
            const auto touched = std::count_if(weight.begin(), weight.end(), [](double w) { return w > 0; });
            out.log.push_back("region: " + std::to_string(touched) +
                              " vertices with weight > 0 took that share of the denoised change; " +
                              std::to_string(input.points.rows() - touched) + " vertices left exactly as they were");
        }
    } else if (region == 0) {
        if (spec.kind == FilterKind::Denoise && out.feature && !cloud && !options.fix_boundary &&
            denoise_bump_holds_boundary(input.triangles, input.points.rows())) {
            options.fix_boundary = true;
            out.log.push_back("open boundary held in place: a lowpass at the bump's size would pull a free boundary"
                              " inwards by about that size");
        }
        out.points = apply_filter(input.points, input.triangles, out.transfer, options, &out.report, input.cache);
        if (spec.kind == FilterKind::Denoise && out.feature) {
            const LowpassForBump lowpass_for = [&](const Points& at, double radius) {
                FeatureEllipsoid bump = *out.feature;
                bump.radius = radius;
                const DenoiseDesign d = design_denoise_from_bump(bump, shape_of(spec, values), order_of(spec, values), out.op);
                // The cache holds the input's mesh, for MeshLab's next preview.
                FilterCache* cache = &at == &input.points ? input.cache : nullptr;
                return LowpassedForBump{apply_filter(at, input.triangles, d.g, options, nullptr, cache), d.g};
            };
            const SelectedBumpDenoise bump = denoise_selected_bump(input.points, out.points, input.triangles,
                                                                   input.selected_faces, out.feature->radius,
                                                                   out.transfer, options, lowpass_for);
            const BumpPatternReport& pattern = bump.pattern;
            const std::string fit = (pattern.learned_profile ? "profile learned from the selected bump and its neighbours, from a Gaussian of width "
                                                             : "Gaussian profile of width ") +
                                    format_number(pattern.width) + " (the selection's radius " +
                                    format_number(out.feature->radius) + "), selected bump " + format_number(pattern.selected_height) +
                                    " high, " + format_number(100 * pattern.unexplained) + " % of it unexplained";
            const std::string refused =
                pattern.side == 0 ? "the selected bump stands neither above nor below the surface around it"
                : pattern.unexplained > bump_max_unexplained
                    ? "the selected bump is not one of a pattern of bumps on a smoother surface (" + fit +
                          ", more than " + format_number(100 * bump_max_unexplained) +
                          " %): the surface's own detail at this size dominates"
                : pattern.unexplained_everywhere > bump_max_unexplained
                    ? "the pattern that explains the selected bump (" + fit + ") does not explain the rest of the"
                      " surface: its " + std::to_string(pattern.bumps + pattern.opposite) + " elements leave " +
                          format_number(100 * pattern.unexplained_everywhere) + " % of what the lowpass removed there"
                          " unexplained, more than " + format_number(100 * bump_max_unexplained) +
                          " %: elsewhere the surface's own detail at this size dominates"
                    : "the selected bump is no bump (" + fit + ": lower than " + format_number(bump_min_height) +
                          " of its radius)";
            const std::string detail = "the lowpass removed detail of " + format_number(bump.removed_detail) +
                                       " RMS across the selection (the threshold: " + format_number(bump_min_height) +
                                       " of its radius, " + format_number(bump_min_height * out.feature->radius) + ")";
            switch (bump.outcome) {
            case SelectedBumpOutcome::PatternRemoved: {
                out.log.push_back(std::string("pattern of bumps removed (the selected one points ") +
                                  (pattern.side > 0 ? "outwards" : "inwards") + "): " + std::to_string(pattern.bumps) +
                                  " bumps of " + std::to_string(pattern.candidates) + " peaks" +
                                  (pattern.opposite ? " and " + std::to_string(pattern.opposite) + " of the other sign (" +
                                                          format_number(100 * pattern.unexplained_one_sign) +
                                                          " % unexplained without them)"
                                                    : std::string()) + ", " + fit +
                                  "; each element at " + format_number(element_sizes[0]) + " to " +
                                  format_number(element_sizes[std::size(element_sizes) - 1]) +
                                  " times its size; volume removed " + format_number(pattern.removed_volume) +
                                  (bump.pattern_radius < out.feature->radius
                                       ? " (fitted again under the lowpass cut for the fitted radius " +
                                             format_number(bump.pattern_radius) + ", narrower than the selection)"
                                       : std::string()));
                const std::string misfit_cut = "cut at radius " + format_number(denoise_misfit_cut_factor * bump.pattern_radius) +
                                               " = " + format_number(denoise_misfit_cut_factor) +
                                               " x the pattern's radius, along the normals";
                out.log.push_back(bump.misfit_lowpassed
                                      ? "then what the pattern did not explain was lowpassed away (" + misfit_cut +
                                            "), moving the enclosed volume by " + format_number(100 * bump.misfit_volume_change) + " %"
                                      : "what the pattern did not explain was left as it is: the lowpass that would take it (" +
                                            misfit_cut + ") would change the enclosed volume by " +
                                            format_number(100 * bump.misfit_volume_change) + " % (more than " +
                                            format_number(100 * denoise_flat_max_volume_change) +
                                            " %), taking parts of the surface itself as small as the bumps");
                break;
            }
            case SelectedBumpOutcome::FlatLowpass: {
                const std::string cut =
                    bump.flat_for_fitted_width
                        ? " (cut for the fitted width " + format_number(bump.flat_radius) + ", narrower than the selection)"
                        : std::string();
                const std::string why =
                    "fell back to the flat lowpass" + cut + " because " + refused + "; " + detail +
                    ": bumps of this size and smaller were smoothed away (the lowpass moved the enclosed volume by " +
                    format_number(100 * bump.flat_volume_change) +
                    " %), and what it removed of the surface they stand on was put back: where what it removed stands out"
                    " of a smoother field by more than " + format_number(base_detail_bump_share) +
                    " of the selected bump's height (" + format_number(bump.base_detail.selected_height) + "), " +
                    format_number(100 * bump.base_detail.bump_area_share) +
                    " % of the surface, it was read as bumps and bridged (" +
                    std::to_string(bump.base_detail.rounds) + " rounds)";
                out.log.push_back("pattern of bumps: " + why);
                out.report.warnings.push_back(why);
                break;
            }
            case SelectedBumpOutcome::Reshapes: {
                const std::string why = refused + "; the flat lowpass at this size would change the enclosed volume by " +
                                        format_number(100 * bump.flat_volume_change) + " % (more than " +
                                        format_number(100 * denoise_flat_max_volume_change) +
                                        " %): it would take parts of the surface itself as small as the bump, so nothing at"
                                        " this size was removed";
                out.log.push_back("pattern of bumps: " + why);
                out.report.warnings.push_back(why);
                break;
            }
            case SelectedBumpOutcome::Unchanged: {
                const std::string why = refused + ", and " + detail + ": nothing at this size was removed";
                out.log.push_back("pattern of bumps: " + why);
                out.report.warnings.push_back(why);
                break;
            }
            }
            out.points = bump.points;
            if (bump.outcome == SelectedBumpOutcome::PatternRemoved || bump.outcome == SelectedBumpOutcome::FlatLowpass) {
                const SamplingDenoise across = denoise_sampling_noise(input.points, input.triangles, order_of(spec, values),
                                                                      sampling_surface(), sampling_options);
                const std::string read = std::string("the sampling-noise rule reads the noise ") +
                                         noise_model_name(across.noise.model) + " (tangential / normal part " +
                                         format_number(across.noise.tangential_ratio) + ")";
                if (across.noise.model != NoiseModel::AlongNormals && !across.input_kept) {
                    out.points = add_motion_across_surface(out.points, input.points, across.points, input.triangles);
                    out.log.push_back("noise across the surface: " + read + ", so the vertices also took its lowpass's motion"
                                      " across the surface (" + across.design.origin + "); along the normals they kept the"
                                      " selected bump's path");
                } else {
                    out.log.push_back("noise across the surface: none to take (" + read +
                                      (across.input_kept ? ", and no lowpass of it scored below leaving the mesh as it is)" : ")"));
                }
            }
            // Nothing removed at the bump's size still leaves the noise a user asks Denoise for:
            // on a smoothed scan with plateau bumps and noise of 0.3 mean edge lengths along the
            // normals, the input's 1.997e-3 RMS from its truth, against 1.652e-3 so.
            if (bump.outcome == SelectedBumpOutcome::Reshapes || bump.outcome == SelectedBumpOutcome::Unchanged) {
                sampling_why = "nothing was removed at the selected bump's size, so per-vertex sampling noise is removed instead";
                sampling_rule();
            }
        }
    } else {
        // The umbrella operator's frequencies are per vertex, not 1/length^2: no feature
        // radius follows from them, so its blend band must be given.
        double s_feature = out.op == Operator::Umbrella ? 0.0 : out.s1_used;
        if (!(s_feature > 0) && spec.kind == FilterKind::PoleZero) {  // the corner the feature would set
            const int corner = choice_of(spec, values, param::feature_corner);
            s_feature = value_of(spec, values, (corner < param::max_pole_zero ? param::zero_prefix : param::pole_prefix) +
                                                   std::to_string(corner % param::max_pole_zero + 1));
        }
        out.points = filter_region(region, value_of(spec, values, param::blend_width), input, out.transfer, options,
                                   s_feature, shape_of(spec, values), out.report, out.log);
    }
    if (sampled && sampled->input_kept) {
        for (const auto& w : out.report.warnings) out.log.push_back("warning: " + w);
    } else {
        log_filter_report(out, options);
    }
    // Whatever made them, a front end writes these coordinates: none may hand on a broken mesh.
    require_finite_output(out.points);
    return out;
}

} // namespace

bool is_point_cloud(const Points& points, const Triangles& triangles) {
    return points.rows() > 0 && triangles.rows() == 0;
}

CloudSurface as_surface_for_filtering(const Points& points, const std::vector<int>& selected_points) {
    std::vector<char> selected(static_cast<size_t>(points.rows()), 0);
    for (int i : selected_points) {
        if (i < 0 || i >= points.rows())
            throw Error("selected point index " + std::to_string(i) + " is out of range (the cloud has " +
                        std::to_string(points.rows()) + " points)");
        selected[i] = 1;
    }
    CloudSurface s;
    s.cloud = point_cloud_laplacian(points);
    const Triangles& t = s.cloud.local_triangles;
    if (!selected_points.empty())
        for (Eigen::Index f = 0; f < t.rows(); ++f)
            if (selected[t(f, 0)] && selected[t(f, 1)] && selected[t(f, 2)]) s.selected_faces.push_back(static_cast<int>(f));
    // A point far from the rest still gets its k neighbours, across the gap: its fan's long
    // triangles pull it towards them, which is what a lowpass does to an outlier, so it is
    // filtered, with a warning, not refused.
    const NeighbourTable& nb = s.cloud.neighbours;
    std::vector<double> spacing(static_cast<size_t>(points.rows()));
    for (Eigen::Index i = 0; i < points.rows(); ++i) spacing[i] = (points.row(nb(i, 0)) - points.row(i)).norm();
    std::vector<double> sorted = spacing;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double median = sorted[sorted.size() / 2], isolated_factor = 10;
    long isolated = 0, first = -1;
    for (size_t i = 0; i < spacing.size(); ++i)
        if (spacing[i] > isolated_factor * median) {
            if (first < 0) first = static_cast<long>(i);
            ++isolated;
        }
    if (isolated > 0)
        s.warnings.push_back(std::to_string(isolated) + " isolated point(s) (point " + std::to_string(first) +
                             " first): the nearest other point is more than " + format_number(isolated_factor) +
                             " times the median spacing " + format_number(median) +
                             " away; their neighbourhoods reach across the gap and the filter pulls them towards it");
    return s;
}

namespace {

RunOutput run_on_mesh(const FilterSpec& spec, const ParameterValues& values, const RunInput& input) {
    // Denoise reads the surface's normals (the noise along them, a bump's height, the volume a
    // closed part encloses); faces wound against their neighbours would cancel them. Only the
    // positions are written back: the mesh's faces stay as they are.
    if (spec.kind == FilterKind::Denoise) {
        const ConsistentOrientation oriented = orient_consistently(input.triangles, input.points.rows());
        if (oriented.turned > 0) {
            RunInput on_oriented{input.points, oriented.triangles, input.selected_faces, input.progress,
                                 input.vertex_quality, input.cache, input.external_solver,
                                 input.complex_factorization, input.selected_vertices};
            RunOutput out = filter_surface(spec, values, on_oriented, nullptr);
            out.log.insert(out.log.begin(),
                           "faces: " + std::to_string(oriented.turned) + " of " + std::to_string(input.triangles.rows()) +
                               " are wound against their neighbours; Denoise took them turned, so that the normals"
                               " and enclosed volumes are the surface's (the mesh's faces are left as they are)");
            return out;
        }
    }
    return filter_surface(spec, values, input, nullptr);
}

// The mesh with its seams welded (weld_seams): each seam's first vertex stands for its copies,
// which leave the mesh the filter sees, and the copies take its result.
RunOutput run_on_welded(const FilterSpec& spec, const ParameterValues& values, const RunInput& input, const SeamWeld& seams) {
    const auto n = static_cast<std::size_t>(input.points.rows());
    std::vector<int> kept(n, -1);
    int count = 0;
    for (std::size_t v = 0; v < n; ++v)
        if (seams.representative[v] == static_cast<int>(v)) kept[v] = count++;
    Points points(count, 3);
    std::vector<double> quality;
    for (std::size_t v = 0; v < n; ++v)
        if (kept[v] >= 0) {
            points.row(kept[v]) = input.points.row(static_cast<Eigen::Index>(v));
            if (input.vertex_quality && input.vertex_quality->size() == n) quality.push_back((*input.vertex_quality)[v]);
        }
    Triangles triangles = seams.triangles;
    for (Eigen::Index f = 0; f < triangles.rows(); ++f)
        for (int k = 0; k < 3; ++k) triangles(f, k) = kept[static_cast<std::size_t>(triangles(f, k))];
    const RunInput on_welded{points, triangles, input.selected_faces, input.progress,
                             input.vertex_quality && input.vertex_quality->size() == n ? &quality : input.vertex_quality,
                             input.cache, input.external_solver, input.complex_factorization, input.selected_vertices};
    RunOutput out = run_on_mesh(spec, values, on_welded);
    if (out.points.rows() == count) {
        Points all(input.points.rows(), 3);
        for (std::size_t v = 0; v < n; ++v)
            all.row(static_cast<Eigen::Index>(v)) = out.points.row(kept[static_cast<std::size_t>(seams.representative[v])]);
        out.points = std::move(all);
    }
    out.log.insert(out.log.begin(), "seams: " + std::to_string(seams.welded) +
                                        " vertices on open edges stand exactly where another does (a seam the file split, by"
                                        " normals, texture coordinates or part): filtered as one surface, so the seams stay"
                                        " closed, and each copy written back with the same position");
    return out;
}

} // namespace

RunOutput run_filter(const FilterSpec& spec, const ParameterValues& values, const RunInput& input) {
    if (!is_point_cloud(input.points, input.triangles)) {
        const SeamWeld seams = weld_seams(input.points, input.triangles);
        return seams.welded ? run_on_welded(spec, values, input, seams) : run_on_mesh(spec, values, input);
    }
    if (!input.selected_faces.empty())
        throw Error("the input is a point cloud (points and no faces), yet " + std::to_string(input.selected_faces.size()) +
                    " faces are given as selected: a cloud's selection is its points (selected vertices)");
    const CloudSurface surface = as_surface_for_filtering(input.points, input.selected_vertices);
    const int region = spec.parameter(param::region) ? choice_of(spec, values, param::region) : 0;
    if (region == 1 && input.selected_vertices.empty())
        throw Error("region = selected faces takes a point cloud's selected points as the region, and none are"
                    " selected: select the region's points first, or choose region = whole mesh");
    // Region = selected faces, and Denoise's bump rule, work on the fans inside the selection.
    const bool uses_selected_faces =
        region == 1 || (spec.kind == FilterKind::Denoise && value_of(spec, values, param::use_selection) != 0);
    if (uses_selected_faces && !input.selected_vertices.empty() && surface.selected_faces.empty())
        throw Error("the " + std::to_string(input.selected_vertices.size()) +
                    " selected points of the cloud enclose none of its local triangles, and " +
                    (region == 1 ? "region = selected faces" : "Denoise's selected bump") +
                    " needs the surface between them: select a patch of neighbouring points");
    RunInput on_surface{input.points,  surface.cloud.local_triangles, surface.selected_faces, input.progress,
                        input.vertex_quality, input.cache, input.external_solver, input.complex_factorization,
                        input.selected_vertices};
    RunOutput out = filter_surface(spec, values, on_surface, &surface);
    std::vector<std::string> head{"point cloud: " + std::to_string(input.points.rows()) + " points, k = " +
                                  std::to_string(surface.cloud.neighbours.cols()) + " neighbours (fans among the nearest " +
                                  std::to_string(surface.cloud.fan_candidates) +
                                  (surface.cloud.fans_from_all_neighbours
                                       ? ", " + std::to_string(surface.cloud.fans_from_all_neighbours) +
                                             " points among all: their nearest lie on a line"
                                       : std::string()) +
                                  "), " +
                                  std::to_string(surface.cloud.local_triangles.rows()) +
                                  " local triangles (the cloud's Laplacian)"};
    for (const auto& w : surface.warnings) head.push_back("warning: " + w);
    out.log.insert(out.log.begin(), head.begin(), head.end());
    out.normals = surface.cloud.normals;
    return out;
}

void require_finite_output(const Points& points) {
    for (Eigen::Index i = 0; i < points.rows(); ++i)
        if (!points.row(i).allFinite())
            throw Error("the filtered coordinates are not finite (vertex " + std::to_string(i) +
                        " first): the transfer function amplifies this mesh too much");
}

Mesh ellipsoid_mesh(const FeatureEllipsoid& e, int levels) {
    Mesh m = icosphere(levels, 1.0);
    for (Eigen::Index i = 0; i < m.points.rows(); ++i) {
        const Eigen::Vector3d local = m.points.row(i).transpose().cwiseProduct(e.radii);
        m.points.row(i) = (e.center + e.axes * local).transpose();
    }
    return m;
}

} // namespace geofilter
