#include "filter_table.h"

#include <set>

namespace geofilter {

namespace {

const char* frequency_note =
    " Sizes become frequencies of the Laplace-Beltrami operator (1/length^2): a sphere-like feature of radius r"
    " has s = 2/r^2, a cylinder-like one s = 1/r^2.";

// The feature's size: what every user sets first. Its default is a fraction of the bounding-box
// diagonal so that it means the same on a mesh of any size and units.
ParameterSpec radius_parameter(double fraction_of_diagonal, const std::string& what) {
    return {param::radius, ParameterType::Length, fraction_of_diagonal, "Feature radius",
            "Radius of the features " + what + ", in mesh units or as a percentage of the bounding-box diagonal."
            " Not used when useSelection measures the selected feature, or when the frequencies are typed.",
            {}};
}

ParameterSpec feature_shape_parameter() {
    return {param::feature_shape, ParameterType::Enum, 0, "Feature shape",
            "Sphere-like (a bump, a nose) or cylinder-like (a leg, a finger): a sphere-like feature of radius r has"
            " frequency 2/r^2, a cylinder-like one 1/r^2.",
            {"Sphere-like (s = 2/r^2)", "Cylinder-like (s = 1/r^2)"}};
}

ParameterSpec use_selection_parameter(const std::string& help) {
    return {param::use_selection, ParameterType::Bool, 1, "Use the selected feature", help, {}};
}

// Where the filter acts; shared by every filtering entry.
ParameterSpec region_parameter() {
    return {param::region, ParameterType::Enum, 0, "Where to filter",
            "The whole mesh; only the selected faces, fading smoothly to untouched across the blend width; or each"
            " vertex by its quality as a weight in [0, 1]. Everything outside the region is left exactly as it was.",
            {"Whole mesh", "Selected faces, blended", "Quality as weight (per vertex)"}};
}

ParameterSpec blend_width_parameter() {
    return {param::blend_width, ParameterType::Length, 0, "Blend width",
            "With Where to filter = selected faces: width of the band around the selection across which the change"
            " fades to zero. 0 = the feature radius.",
            {}};
}

ParameterSpec fix_boundary_parameter() {
    return {param::fix_boundary, ParameterType::Bool, 0, "Keep open boundaries in place",
            "Hold the vertices of holes and cut edges where they are. Off: the paper's free boundary, which moves with"
            " the surface.",
            {}};
}

// The expert's end of every dialog: how the sparse systems are solved.
std::vector<ParameterSpec> solver_parameters() {
    return {
        {param::solver, ParameterType::Enum, 0, "Solver (expert)",
         "Factored: sparse Cholesky, exact and fast at any size. Jacobi-PCG: the paper's conjugate gradients, slow for"
         " wide features; kept as a reference.",
         {"Factored (sparse Cholesky)", "Jacobi-PCG (paper)"}},
        {param::tolerance, ParameterType::Float, 1e-7, "Accuracy (expert)",
         "The result is guaranteed within this fraction of the bounding-box diagonal of the exact filter (RMS).", {}},
        {param::max_iterations, ParameterType::Int, 100000, "Iteration cap (expert)",
         "Cap on conjugate-gradient iterations per solve; reaching it is an error and the mesh is left as it was.", {}},
    };
}

// region, blendWidth and fixBoundary, then the solver's three: every filtering entry ends with them.
void append_where_and_how(std::vector<ParameterSpec>& p) {
    p.push_back(region_parameter());
    p.push_back(blend_width_parameter());
    p.push_back(fix_boundary_parameter());
    for (auto& q : solver_parameters()) p.push_back(std::move(q));
}

std::vector<ParameterSpec> second_order_parameters(const SecondOrderSpec& d, double radius_fraction,
                                                   const std::string& radius_what) {
    std::vector<ParameterSpec> p = {
        radius_parameter(radius_fraction, radius_what),
        feature_shape_parameter(),
        use_selection_parameter("Take the feature radius from the selected faces (an ellipsoid fitted to them; the log"
                                " says the radius it measured). On by default when faces are selected."),
        {param::G0, ParameterType::Float, d.G0, "Gain of the overall shape (G0)",
         "1 keeps the shape and size, 0.5 halves it about the centroid, 0 removes it.", {}},
        {param::G1, ParameterType::Float, d.G1, "Gain at the feature size (G1)",
         "Above 1 exaggerates features of the feature radius, below 1 removes them. Must differ from 1 and from the"
         " detail gain.",
         {}},
        {param::Ginf, ParameterType::Float, d.Ginf, "Gain of the finest detail (Ginf)",
         "0 removes noise and detail much smaller than the feature, 1 keeps it, above 1 sharpens it.", {}},
    };
    append_where_and_how(p);
    const std::string ratio = format_number(d.s2 / d.s1);
    p.insert(p.end() - 3,
             {{param::s1, ParameterType::Float, 0, "Frequency s1 (expert)",
               "The paper's feature frequency, where the gain peaks or dips (eq. 15). 0 = from the feature radius; a"
               " typed s1 > 0 is used as it is and the radius is ignored (scripts that set s1 and s2 run as before).",
               {}},
              {param::s2, ParameterType::Float, 0, "Frequency s2 (expert)",
               "The paper's unit-gain frequency, G(s2) = 1. 0 = " + ratio +
                   " s1, this filter's shape; a radius or a selection keeps the typed ratio s2/s1 when both are typed.",
               {}}});
    return p;
}

FilterSpec second_order(const std::string& title, const std::string& python, const std::string& cli, const std::string& what,
                        const SecondOrderSpec& reference, double radius_fraction, const std::string& radius_what) {
    FilterSpec f{"GeoFilter: " + title,
                 python,
                 cli,
                 FilterKind::SecondOrder,
                 what + " Set the feature radius, or select the feature and keep Use the selected feature on." +
                     frequency_note +
                     " Second-order GeoFilter (Kim &amp; Rossignac 2005, eq. 9 and 15): G(0) = G0, G(s1) = G1 (an"
                     " extremum), G(s2) = 1, G(inf) = Ginf.",
                 second_order_parameters(reference, radius_fraction, radius_what)};
    f.reference = reference;
    return f;
}

FilterSpec pole_zero() {
    std::vector<ParameterSpec> p;
    p.push_back({param::radius, ParameterType::Length, 0, "Feature radius (0 = corners as typed)",
                 "Sets the chosen corner to the frequency of a feature of this radius, the other corners keeping their"
                 " ratios to it (mesh units or % of the diagonal). 0 = the corner frequencies as typed.",
                 {}});
    p.push_back(feature_shape_parameter());
    p.push_back(use_selection_parameter("Set the chosen corner from the selected faces' radius instead; the other corners"
                                        " keep their ratios. On by default when faces are selected."));
    std::vector<std::string> corners;
    for (int i = 0; i < param::max_pole_zero; ++i) corners.push_back("z" + std::to_string(i + 1));
    for (int i = 0; i < param::max_pole_zero; ++i) corners.push_back("p" + std::to_string(i + 1));
    p.push_back({param::feature_corner, ParameterType::Enum, 0, "Corner the feature sets",
                 "Which corner frequency the radius or the selection sets (it must be in use).", corners});
    p.push_back({param::G0, ParameterType::Float, 1, "Gain of the overall shape (G0)", "Gain at frequency 0.", {}});
    const double zeros[param::max_pole_zero] = {100, 400, 0, 0}, poles[param::max_pole_zero] = {50, 800, 0, 0};
    for (int i = 0; i < param::max_pole_zero; ++i)
        p.push_back({param::zero_prefix + std::to_string(i + 1), ParameterType::Float, zeros[i], "zero " + std::to_string(i + 1),
                     "Corner frequency where the gain turns up by 20 dB/decade (0 = unused).", {}});
    for (int i = 0; i < param::max_pole_zero; ++i)
        p.push_back({param::pole_prefix + std::to_string(i + 1), ParameterType::Float, poles[i], "pole " + std::to_string(i + 1),
                     "Corner frequency where the gain turns down by 20 dB/decade (0 = unused).", {}});
    append_where_and_how(p);
    return {"GeoFilter: Pole-Zero",
            "apply_geofilter_pole_zero",
            "polezero",
            FilterKind::PoleZero,
            "First-order GeoFilter designed by asymptotes (Kim &amp; Rossignac 2005, eq. 16): the gain turns up by"
            " 20 dB/decade at each zero and down at each pole; two zeros between two poles make a band-stop. Each pole"
            " is one sparse solve, the cheapest GeoFilter." +
                std::string(frequency_note),
            p};
}

// The operator choice every Butterworth-based entry shares; index 0 lets the filter pick.
// The Butterworth order n of the higher-order filters, 4 by default.
ParameterSpec order_parameter(const std::string& help) {
    return {param::order, ParameterType::Int, 4, "Steepness n, 1-8 (expert)", help, {}};
}

ParameterSpec operator_parameter(const std::string& automatic) {
    return {param::laplace_operator, ParameterType::Enum, 0, "Laplacian (expert)",
            "Cotangent: the paper's. Intrinsic Delaunay: cotangent weights after intrinsic flips, never negative, so"
            " irregular triangles cannot fold faces. Umbrella: Taubin's per-vertex graph Laplacian, blind to edge"
            " lengths (its frequencies are not sizes). Automatic: " +
                automatic,
            {"Automatic", "Cotangent", "Intrinsic Delaunay", "Umbrella (per-vertex)"}};
}


FilterSpec butterworth_lowpass() {
    std::vector<ParameterSpec> p;
    p.push_back(radius_parameter(0.04, "at the cutoff: larger ones are kept, smaller ones removed, those of this radius"
                                       " halved"));
    p.push_back(feature_shape_parameter());
    p.push_back(use_selection_parameter("Take the cutoff radius from the selected faces (the log says the radius it"
                                        " measured). On by default when faces are selected."));
    p.push_back(order_parameter("Steepness: beyond the cutoff the gain falls by 20 n dB per decade of frequency."));
    p.push_back(operator_parameter("cotangent."));
    append_where_and_how(p);
    p.insert(p.end() - 3, {param::cutoff, ParameterType::Float, 0, "Cutoff frequency (expert)",
                           "The frequency sc where the gain is 1/2. 0 = from the feature radius; a typed cutoff > 0 is"
                           " used as it is and the radius is ignored.",
                           {}});
    return {"GeoFilter: Butterworth Lowpass",
            "apply_geofilter_butterworth_lowpass",
            "butterworth",
            FilterKind::Butterworth,
            "Removes features smaller than the feature radius and keeps larger ones unchanged: the maximally flat lowpass"
            " G(s) = 1/(1 + (s/sc)^n), no bump in the gain, so no volume change." +
                std::string(frequency_note),
            p};
}

FilterSpec denoise() {
    std::vector<ParameterSpec> p;
    p.push_back(use_selection_parameter("On: the selected faces are one bump of a pattern to remove, and bumps like it go."
                                        " Off: per-vertex sampling noise is removed, measured on the mesh. On by default"
                                        " when faces are selected."));
    p.push_back(feature_shape_parameter());
    p.push_back(order_parameter("Steepness of the lowpass that separates the noise: 20 n dB per decade of frequency."));
    p.push_back(operator_parameter("the cotangent with a selection; without, the umbrella and the intrinsic Delaunay"
                                   " operators are both tried and the better-scoring one is kept."));
    append_where_and_how(p);
    for (ParameterSpec& q : p)
        if (q.name == param::fix_boundary)
            q.help += " With one bump selected, always held: a lowpass at a bump's size would pull a free"
                      " boundary inwards by about that size.";
    return {"GeoFilter: Denoise",
            "apply_geofilter_denoise",
            "denoise",
            FilterKind::Denoise,
            "Removes noise with nothing to set. Nothing selected: a scan's per-vertex sampling noise goes, with the"
            " lowpass the filter picks on the mesh by its estimated distance to the noise-free surface (Stein's unbiased"
            " risk estimate), then fitted to its face normals smoothed across faces but not across sharp edges where"
            " that scores closer still; one bump selected: the bumps like it go, with what is left of them at their size,"
            " and larger shapes stay;"
            " with Where to filter set, only that region is denoised. The log says what was measured and chosen, and why.",
            p};
}

// What only an expert sets: the frequencies of the paper's equations and the solver's knobs.
void mark_expert_parameters(std::vector<FilterSpec>& table) {
    const std::set<std::string> expert = {param::s1,    param::s2,     param::cutoff,    param::order,
                                          param::laplace_operator, param::solver, param::tolerance,
                                          param::max_iterations};
    for (auto& f : table)
        for (auto& p : f.parameters) p.expert = expert.count(p.name) > 0;
}

std::vector<FilterSpec> make_table() {
    std::vector<FilterSpec> t;
    // Defaults are the paper's figures where those are stable (docs/paper-notes.md §9); the
    // highpass family's printed example is not, so its default is a stable member of it.
    // The reference designs are the paper's figures where those are stable (docs/paper-notes.md
    // §9); the highpass family's printed example is not, so its reference is a stable member of
    // it. The default radii are a few percent of the diagonal: a visible feature on any mesh.
    t.push_back(second_order("Lowpass", "apply_geofilter_lowpass", "lowpass",
                             "Removes features smaller than the feature radius and keeps larger ones (paper Fig. 12).",
                             {25, 50, 1, 1.1, 0}, 0.04, "to keep: smaller ones are removed"));
    t.push_back(second_order("Bandpass", "apply_geofilter_bandpass", "bandpass",
                             "Keeps only features near the feature radius: the overall shape and the finest detail go.",
                             {25, 100, 0, 2, 0}, 0.05, "to keep"));
    t.push_back(second_order("Highpass", "apply_geofilter_highpass", "highpass",
                             "Keeps features smaller than the feature radius and removes the overall shape: the mesh"
                             " collapses to its detail.",
                             {100, 25, 0, 1.1, 1}, 0.05, "above which the shape is removed"));
    t.push_back(second_order("Notch", "apply_geofilter_notch", "notch",
                             "Removes features of the feature radius and keeps everything else (paper Fig. 9, band stop).",
                             {630, 1260, 1, 0.01, 1.1}, 0.02, "to remove"));
    t.push_back(second_order("Band Exaggeration", "apply_geofilter_band_exaggeration", "exaggerate",
                             "Exaggerates features of the feature radius by the gain G1 (paper Fig. 10).",
                             {25, 60, 1, 3, 0.9}, 0.05, "to exaggerate"));
    t.push_back(second_order("Custom", "apply_geofilter_custom", "custom",
                             "Any second-order GeoFilter: set the gains, or type the five numbers of eq. 15.",
                             {60, 120, 1, 2, 0.9}, 0.05, "at which the gain is G1"));
    t.push_back(pole_zero());
    t.push_back({"GeoFilter: Measure Selected Feature",
                 "compute_geofilter_feature_measure",
                 "measure",
                 FilterKind::Measure,
                 "Fits an ellipsoid to the selected faces (area-weighted covariance frame, bounding box in that frame;"
                 " paper section 6), adds it as a new layer and logs its radii and the feature's frequency: s = 2/r^2 if"
                 " sphere-like, 1/r^2 if cylinder-like, r blending the means of the adjacent pairs of radii by how round each"
                 " pair is.",
                 {}});
    t.push_back(butterworth_lowpass());
    t.push_back(denoise());
    mark_expert_parameters(t);
    return t;
}

} // namespace

const ParameterSpec* FilterSpec::parameter(const std::string& n) const {
    for (const auto& p : parameters)
        if (p.name == n) return &p;
    return nullptr;
}

const std::vector<FilterSpec>& filter_table() {
    static const std::vector<FilterSpec> table = make_table();
    return table;
}

const FilterSpec* find_filter(const std::string& name) {
    for (const auto& f : filter_table())
        if (f.name == name || f.python_name == name || f.cli_name == name) return &f;
    return nullptr;
}

} // namespace geofilter
