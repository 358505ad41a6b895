#include "filter_table.h"

namespace geofilter {

namespace {

const char* frequency_note =
    " Frequencies are eigenvalues of the Laplace-Beltrami operator, in 1/length^2 of the mesh's units:"
    " a sphere-like feature of radius r has s = 2/r^2, a cylinder-like one s = 1/r^2"
    " (so s = 25 is a nose of radius 0.28, s = 630 a bump of radius 0.056).";

// Where the filter acts (issue 11); shared by every filtering entry.
ParameterSpec region_parameter() {
    return {param::region, ParameterType::Enum, 0, "region: where to filter",
            "Whole mesh: every vertex (the paper's filter). Selected faces: only the selected faces, the change fading"
            " smoothly to zero across a band of width blendWidth around them; everything beyond is left exactly as it"
            " was. Quality as weight: each vertex takes the fraction w = its vertex quality of the change (0 = untouched,"
            " 1 = fully filtered; values outside [0, 1] are clamped, NaN refused). The region is filtered as its own"
            " domain with the untouched vertices around it held fixed.",
            {"Whole mesh", "Selected faces, blended", "Quality as weight (per vertex)"}};
}

ParameterSpec blend_width_parameter() {
    return {param::blend_width, ParameterType::Float, 0, "blendWidth: fade band (0 = auto)",
            "With region = Selected faces: width, in mesh units along the surface, of the band around the selection"
            " across which the change fades to zero (with zero slope at both ends, so the surface stays smooth). 0 ="
            " auto: the radius of the feature at s1 (sqrt(2/s1) sphere-like, sqrt(1/s1) cylinder-like). Not used by the"
            " other regions.",
            {}};
}

std::vector<ParameterSpec> second_order_parameters(const SecondOrderSpec& d) {
    return {
        {param::s1, ParameterType::Float, d.s1, "s1: feature frequency",
         "Frequency where the gain peaks (or dips): G(s1) = G1 and G'(s1) = 0. s1 = 2/r^2 for a sphere-like feature of"
         " radius r, 1/r^2 for a cylinder-like one. With useSelection on, s1 is measured from the selected faces"
         " instead.",
         {}},
        {param::s2, ParameterType::Float, d.s2, "s2: unit-gain frequency",
         "Frequency where the gain returns to 1: G(s2) = 1. With useSelection on, s2 keeps its ratio s2/s1 to the"
         " measured s1. s2 = 2 s1 with G0 = 1 and Ginf = 0 gives the steepest (40 dB/decade) lowpass.",
         {}},
        {param::G0, ParameterType::Float, d.G0, "G0: gain at s = 0",
         "Gain of the lowest frequencies (the overall shape and size): 1 keeps the size, 0.5 halves it about the"
         " centroid, 0 removes it (bandpass, highpass).",
         {}},
        {param::G1, ParameterType::Float, d.G1, "G1: gain at s1",
         "Gain at the feature frequency s1: above 1 exaggerates features of that size, below 1 removes them (notch)."
         " Must differ from 1 and from Ginf.",
         {}},
        {param::Ginf, ParameterType::Float, d.Ginf, "Ginf: gain at high frequency",
         "Gain of the finest detail and noise (s -> infinity): 0 removes noise, 1 keeps it, above 1 sharpens it.", {}},
        {param::use_selection, ParameterType::Bool, 1, "useSelection: s1 from the selected feature",
         "Measure s1 from the selected faces: an ellipsoid is fitted to them (covariance frame, bounding box) and its"
         " radius r gives s1 = 2/r^2 or 1/r^2 (see featureShape); s2 keeps its ratio to s1. Default: on when faces"
         " are selected.",
         {}},
        {param::feature_shape, ParameterType::Enum, 0, "featureShape",
         "How the selected feature's radius r becomes a frequency: sphere-like (a bump, a nose) s = 2/r^2,"
         " cylinder-like (a leg, a finger) s = 1/r^2. r blends the means of the two adjacent pairs of ellipsoid radii,"
         " weighted by how round each pair is: the two wide radii for a bump, the two narrow ones for a tube, all"
         " three for a sphere.",
         {"Sphere-like (s = 2/r^2)", "Cylinder-like (s = 1/r^2)"}},
        {param::fix_boundary, ParameterType::Bool, 0, "fixBoundary: keep open boundaries in place",
         "Keep the vertices of open boundaries (holes, cut edges) exactly where they are and filter the interior"
         " relative to them. Off: the paper's free boundary, where open edges move with the surface (a lowpass"
         " shrinks a hole's rim like the rest of the shape).",
         {}},
        {param::solver, ParameterType::Enum, 0, "solver",
         "Factored: sparse Cholesky factorisations, exact and fast whatever s1. Jacobi-PCG: the paper's"
         " conjugate-gradient method, slow for small s1 (wide features); kept as a reference.",
         {"Factored (sparse Cholesky)", "Jacobi-PCG (paper)"}},
        {param::tolerance, ParameterType::Float, 1e-7, "tolerance: accuracy of the result",
         "The solver stops once its error bound guarantees that the filtered surface is within this fraction of"
         " the bounding-box diagonal of the exact result (area-weighted RMS distance). The bound holds on any mesh;"
         " the direct (factored) solves are exact up to rounding.",
         {}},
        {param::max_iterations, ParameterType::Int, 100000, "maxIterations",
         "Cap on conjugate-gradient iterations per solve; reaching it is reported as an error, the mesh is left as"
         " it was.",
         {}},
        region_parameter(),
        blend_width_parameter(),
    };
}

FilterSpec second_order(const std::string& title, const std::string& python, const std::string& cli, const std::string& what,
                        const SecondOrderSpec& defaults) {
    return {"GeoFilter: " + title,
            python,
            cli,
            FilterKind::SecondOrder,
            what +
                " Second-order GeoFilter (Kim &amp; Rossignac 2005, eq. 9 and 15): the gain G(s) is designed from five"
                " numbers, G(0) = G0, G(s1) = G1 (an extremum), G(s2) = 1, G(inf) = Ginf." +
                frequency_note +
                " Select the feature (e.g. with the selection tools) and keep useSelection on to take s1 from its size.",
            second_order_parameters(defaults)};
}

// solver, tolerance, maxIterations, featureShape, fixBoundary, region and blendWidth, as the second-order
// entries have them.
void append_shared(std::vector<ParameterSpec>& p) {
    for (const auto& shared : second_order_parameters({}))
        if (shared.name == param::feature_shape || shared.name == param::fix_boundary || shared.name == param::solver ||
            shared.name == param::tolerance || shared.name == param::max_iterations || shared.name == param::region ||
            shared.name == param::blend_width)
            p.push_back(shared);
}

FilterSpec pole_zero() {
    std::vector<ParameterSpec> p;
    p.push_back({param::G0, ParameterType::Float, 1, "G0: gain at s = 0", "Gain of the lowest frequencies.", {}});
    const double zeros[param::max_pole_zero] = {100, 400, 0, 0}, poles[param::max_pole_zero] = {50, 800, 0, 0};
    for (int i = 0; i < param::max_pole_zero; ++i)
        p.push_back({param::zero_prefix + std::to_string(i + 1), ParameterType::Float, zeros[i], "zero " + std::to_string(i + 1),
                     "Corner frequency where the gain turns up by 20 dB/decade (0 = unused).", {}});
    for (int i = 0; i < param::max_pole_zero; ++i)
        p.push_back({param::pole_prefix + std::to_string(i + 1), ParameterType::Float, poles[i], "pole " + std::to_string(i + 1),
                     "Corner frequency where the gain turns down by 20 dB/decade (0 = unused).", {}});
    std::vector<std::string> corners;
    for (int i = 0; i < param::max_pole_zero; ++i) corners.push_back("z" + std::to_string(i + 1));
    for (int i = 0; i < param::max_pole_zero; ++i) corners.push_back("p" + std::to_string(i + 1));
    p.push_back({param::use_selection, ParameterType::Bool, 1, "useSelection: corner from the selected feature",
                 "Set the corner chosen by featureCorner to the selected feature's frequency (2/r^2 or 1/r^2); the other"
                 " corners keep their ratios to it. Default: on when faces are selected.",
                 {}});
    p.push_back({param::feature_corner, ParameterType::Enum, 0, "featureCorner",
                 "Which corner frequency the selected feature sets (it must be in use).", corners});
    append_shared(p);
    return {"GeoFilter: Pole-Zero",
            "apply_geofilter_pole_zero",
            "polezero",
            FilterKind::PoleZero,
            "First-order GeoFilter designed by asymptotes (Kim &amp; Rossignac 2005, eq. 16):"
            " G(s) = G0 (p1 p2 ../z1 z2 ..) (s + z1)(s + z2)../((s + p1)(s + p2)..). On a log-log plot G turns up by"
            " 20 dB/decade at each zero and down by 20 dB/decade at each pole (a band-stop: two zeros between two"
            " poles). Each pole is one sparse solve, the cheapest GeoFilter." +
                std::string(frequency_note),
            p};
}

// The operator choice every Butterworth-based entry shares; index 0 lets the filter pick.
// The Butterworth order n of the higher-order filters, 4 by default.
ParameterSpec order_parameter(const std::string& help) {
    return {param::order, ParameterType::Int, 4, "order: steepness n (1-8)", help, {}};
}

ParameterSpec operator_parameter(const std::string& automatic) {
    return {param::laplace_operator, ParameterType::Enum, 0, "operator: Laplacian",
            "The discrete Laplacian whose frequencies the filter cuts. Cotangent: the paper's (frequencies in"
            " 1/length^2). Intrinsic Delaunay: cotangent weights after intrinsic edge flips, never negative, so noisy"
            " or irregular triangles cannot make the filter fold faces (same units). Umbrella: Taubin's graph"
            " Laplacian normalised by the degree, frequencies per vertex in [0, 2], blind to edge lengths. Automatic: " +
                automatic,
            {"Automatic", "Cotangent", "Intrinsic Delaunay", "Umbrella (per-vertex)"}};
}


FilterSpec butterworth_lowpass() {
    std::vector<ParameterSpec> p;
    p.push_back({param::cutoff, ParameterType::Float, 25, "cutoff: frequency sc",
                 "Frequency where the gain is 1/2: features of radius r > sqrt(2/sc) (sphere-like) are kept with a gain"
                 " of almost exactly 1, smaller ones removed. With useSelection on, sc is the selected feature's"
                 " frequency (2/r^2 or 1/r^2).",
                 {}});
    p.push_back(order_parameter("Steepness: beyond the cutoff the gain falls by 20 n dB per decade; below it the gain"
                                " stays within (s/sc)^n of 1. Each order is one sparse solve (a pair of orders one"
                                " conjugate-gradient solve)."));
    p.push_back({param::use_selection, ParameterType::Bool, 1, "useSelection: cutoff from the selected feature",
                 "Set sc to the selected feature's frequency (2/r^2 sphere-like, 1/r^2 cylinder-like): features of that"
                 " size are halved, smaller ones removed. Default: on when faces are selected.",
                 {}});
    p.push_back(operator_parameter("cotangent."));
    append_shared(p);
    return {"GeoFilter: Butterworth Lowpass",
            "apply_geofilter_butterworth_lowpass",
            "butterworth",
            FilterKind::Butterworth,
            "Maximally flat lowpass of order n: G(s) = 1/(1 + (s/sc)^n). The gain stays at 1 (no bump, so no volume"
            " change) up to the cutoff and falls by 20 n dB/decade beyond it, applied as a cascade of first- and"
            " second-order GeoFilter sections (the paper's note on higher orders)." +
                std::string(frequency_note),
            p};
}

FilterSpec denoise() {
    std::vector<ParameterSpec> p;
    p.push_back({param::use_selection, ParameterType::Bool, 1, "useSelection: remove bumps like the selected one",
                 "On: the selected faces are one bump of the pattern to remove; bumps of that size and smaller go"
                 " down to the surface they stand on, larger features stay (cutoff radius twice the bump's). Off: remove per-vertex"
                 " sampling noise using only the mesh. Default: on when faces are selected.",
                 {}});
    p.push_back(order_parameter("Order of the Butterworth lowpass (steepness, 20 n dB/decade)."));
    p.push_back(operator_parameter("cotangent with a selection; without, both the umbrella (per-vertex) and the"
                                   " intrinsic Delaunay operator are tried and the better-scoring one is kept."));
    append_shared(p);
    return {"GeoFilter: Denoise",
            "apply_geofilter_denoise",
            "denoise",
            FilterKind::Denoise,
            "Removes noise without tuning. With a selection: select one bump of a pattern (bumps, dents, a"
            " texture) and the bumps like it are removed: what a 4th-order Butterworth lowpass cut at twice the"
            " bump's radius removes is fitted by a pattern of Gaussian bumps (one width, fitted on the selected bump"
            " and its neighbours; one height per bump), which is subtracted, so the bumps' volume goes and the rest"
            " of the surface stays as it was; when no pattern explains the selected bump, that flat lowpass is kept"
            " instead (the mesh is left as it was only if the lowpass removed nothing there) and the log says why."
            " A selection of a quarter of the mesh's area or more is no bump: it gets the rule without a selection."
            " With a region (selected faces or quality as weight) the selection is the region, not a bump: the rule"
            " without a selection runs and its result is faded in by the region's weight, the rest left exactly as"
            " it was. Without: per-vertex sampling noise is removed by the same lowpass,"
            " its cutoff and operator (Taubin's umbrella or the intrinsic Delaunay cotangent) chosen on the mesh"
            " among 11 candidates by their estimated distance to the noise-free surface (Stein's unbiased risk"
            " estimate; the noise's strength and direction, along the normals or in every direction, measured on"
            " the mesh; noise along the normals leaves the vertices right across the surface,"
            " so there only the lowpass's motion along the normals is kept, and no vertex moves farther than 3"
            " standard deviations of the noise: farther, the lowpass would be reshaping a toe or a tip, not"
            " removing noise), and closed parts keep their volume;"
            " the log lists every candidate's score (each operator's cutoffs are searched downhill from the"
            " middle one, so those beyond a higher score are not run).",
            p};
}

std::vector<FilterSpec> make_table() {
    std::vector<FilterSpec> t;
    // Defaults are the paper's figures where those are stable (docs/paper-notes.md §9); the
    // highpass family's printed example is not, so its default is a stable member of it.
    t.push_back(second_order("Lowpass", "apply_geofilter_lowpass", "lowpass",
                             "Removes features smaller than the one at s1 and keeps larger ones (paper Fig. 12).",
                             {25, 50, 1, 1.1, 0}));
    t.push_back(second_order("Bandpass", "apply_geofilter_bandpass", "bandpass",
                             "Keeps only features near the size at s1 (G0 = Ginf = 0): the mesh's overall shape is removed.",
                             {25, 100, 0, 2, 0}));
    t.push_back(second_order("Highpass", "apply_geofilter_highpass", "highpass",
                             "Keeps features smaller than the one at s1 and removes the overall shape (s1 > s2, G0 = 0):"
                             " the mesh collapses to its detail.",
                             {100, 25, 0, 1.1, 1}));
    t.push_back(second_order("Notch", "apply_geofilter_notch", "notch",
                             "Removes features of the size at s1 and keeps everything else (paper Fig. 9, band stop).",
                             {630, 1260, 1, 0.01, 1.1}));
    t.push_back(second_order("Band Exaggeration", "apply_geofilter_band_exaggeration", "exaggerate",
                             "Exaggerates features of the size at s1 by G1 (paper Fig. 10).", {25, 60, 1, 3, 0.9}));
    t.push_back(second_order("Custom", "apply_geofilter_custom", "custom",
                             "Any second-order GeoFilter: set the five numbers yourself.", {60, 120, 1, 2, 0.9}));
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
