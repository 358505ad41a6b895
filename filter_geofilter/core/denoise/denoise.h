// The rules of the Denoise filter: which Butterworth lowpass, on which operator, from what
// the user gives (a selected bump) or from the mesh alone. The constants were chosen by
// measurement (experiments/compare_denoise.py, docs/results.md), not tuned per mesh.
#pragma once

#include "core/denoise/base_detail.h"
#include "core/denoise/bump_pattern.h"
#include "core/design/butterworth.h"
#include "core/feature/feature.h"
#include "core/filter/filter.h"
#include "core/denoise/noise_direction.h"
#include "core/denoise/motion_bound.h"
#include "core/denoise/noise_variance.h"
#include "core/denoise/normal_fit.h"
#include "core/denoise/normal_motion.h"
#include "core/operators/operators.h"
#include "core/denoise/risk_estimate.h"
#include "core/denoise/volume.h"

#include <cstdint>
#include <iterator>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace geofilter {

// A selected bump of radius r is one of a pattern to remove: cut at the frequency of
// features twice its size, so bumps of that size and smaller go while the flat passband
// keeps larger features and the volume. (Measured in docs/results.md section 4: the best
// cutoff radius lay at 1.5-2.5x the bump's; at 3-4x the filter eats features 5-8x larger.)
constexpr double denoise_radius_factor = 2.0;
constexpr int denoise_order = 4;

struct DenoiseDesign {
    TransferFunction g;
    Operator op;
    double cutoff;       // in the operator's frequency units
    std::string origin;  // where the cutoff came from, for the log
};

// From a measured bump (sphere-like s = 2/R^2 or cylinder-like 1/R^2 with R = 2 r).
DenoiseDesign design_denoise_from_bump(const FeatureEllipsoid& bump, FeatureShape shape, int order, Operator op);

// A selection is one bump of a pattern only while a lowpass cut at denoise_radius_factor
// times its radius leaves the rest of the mesh's shape alone. That lowpass acts on discs of
// denoise_radius_factor^2 = 4 times the bump's area; a selection of a quarter of the mesh's
// area or more makes that disc the whole mesh, so the "bump" is the mesh (in MeshLab, often
// a selection left over from another tool) and the sampling-noise rule serves it instead.
// A bump the tests select covers 0.2-1 % of its mesh (the ball of its radius on the unit
// sphere), far below; a leftover selection, typically half the mesh or more, far above.
constexpr double denoise_largest_bump_share = 0.25;

// The share of the mesh's area the faces cover (0 for a mesh of no area).
double selected_area_share(const Points& points, const Triangles& triangles, const std::vector<int>& faces);

// What Denoise did with a selected bump.
enum class SelectedBumpOutcome {
    PatternRemoved,  // the pattern of bumps like it was fitted and subtracted
    FlatLowpass,     // no pattern explained it: the flat lowpass at its scale was kept instead
    Unchanged,       // no pattern, and the lowpass removed no detail there: nothing to remove
    Reshapes,        // no pattern, and the flat lowpass would change the enclosed volume: left as it was
};

// A lowpass cut at a bump's size keeps a pattern's mean height, so it leaves the volume a
// closed surface encloses nearly as it was: on the tuning half of experiments/generalize_denoise
// the patterns on spheres and tori that fell back to it moved it by at most 0.07 %. Where it
// moves it more than this (the volume Denoise's results are held to), it is taking parts of
// the surface itself that are as small as the bumps (a scan's legs, ears and tail: 2.2-2.5 %
// on the tuning half's smoothed scans, which it left 3-6x farther from the truth than their
// input), and the flat fallback is refused.
constexpr double denoise_flat_max_volume_change = 0.003;

struct SelectedBumpDenoise {
    Points points;
    SelectedBumpOutcome outcome = SelectedBumpOutcome::Unchanged;
    BumpPatternReport pattern;
    // Area-weighted RMS, about its mean, of how far the lowpass moved the selection's vertices
    // along the normals: the detail it removed there (a curved surface's even shrinking is no detail).
    double removed_detail = 0;
    double flat_volume_change = 0;  // the flat lowpass's largest relative change of a closed component's volume
    double flat_radius = 0;         // the bump radius the flat lowpass kept was cut for (0: none was kept)
    bool flat_for_fitted_width = false;  // that radius is the fitted width, not the selection's footprint
    double pattern_radius = 0;      // the bump radius the removed pattern was fitted under (the selection's, or the fitted width when narrower)
    BaseDetailReport base_detail;   // the base's detail put back into the flat lowpass (with_base_detail)
    // After a pattern was removed: whether its misfit was lowpassed away (denoise_misfit_cut_factor),
    // and that lowpass's largest relative change of a closed component's volume.
    bool misfit_lowpassed = false;
    double misfit_volume_change = 0;
};

// Whether the lowpass for a selected bump holds the mesh's open boundary in place: whenever
// it has one. A lowpass at a bump's size pulls a free boundary inwards by about that size,
// and the pull reaches far inside: on the tuning half's open patches the free lowpass ended
// 0.95-3.3x the input's RMS distance to the truth, the held one 0.73-0.77x.
bool denoise_bump_holds_boundary(const Triangles& triangles, Eigen::Index vertex_count);

// The Denoise lowpass designed for a bump of `radius` (design_denoise_from_bump with the
// selection's shape, order and operator): its transfer function and `points` lowpassed by it.
struct LowpassedForBump {
    Points points;
    TransferFunction g;
};
using LowpassForBump = std::function<LowpassedForBump(const Points& points, double radius)>;

// A fitted pattern leaves its misfit behind: elements of other sizes and profiles, peaks the
// fit did not take, each at about the pattern's own size. A lowpass cut at this many times
// the pattern's radius, applied after the pattern is subtracted, takes that misfit off while
// the pattern's mean height, which such a lowpass keeps, is already gone with the pattern.
// Chosen on the tuning half of experiments/generalize_denoise (docs/denoise.md): on its 12
// cases that removed a pattern, 1.5 and 2 (the flat fallback's cut) each did best on six with
// the same total; 1.5 brought every one closer to the truth, 2 took one farther, 1 was behind
// both. Any cut from 1 to 2 helped all but that one.
constexpr double denoise_misfit_cut_factor = 1.5;

// Denoise's rule for one selected bump (`bump_faces`, measured radius `bump_radius`):
// `lowpassed` is the input lowpassed by `g` (design_denoise_from_bump, applied with
// `options`). The pattern of bumps like it is removed (remove_bump_pattern). When no pattern
// explains the selection (bumps of another profile, a texture, noise as large as the bump),
// returning the input would be a silent no-op; the flat lowpass's motion along the normals
// (normal_motion.h), with the base's own detail that it removed put back (with_base_detail),
// is returned instead when it removed detail at the selection higher than bump_min_height of
// its radius, the height below which a selection is a flat patch; below that the input is
// returned unchanged, and so it is when the flat lowpass changes a closed component's volume
// by more than denoise_flat_max_volume_change. The flat lowpass is cut for the width of the
// profile fitted to the selected bump where that is narrower than the selection (made by
// `lowpass_for`), else at the selection (`lowpassed`): a user's selection is a footprint,
// often wider than the bump. For the same reason a removed pattern whose profile is narrower
// than the selection is fitted again under the lowpass cut for that width. A removed pattern's
// misfit is then lowpassed (denoise_misfit_cut_factor), along the normals only, unless that
// lowpass too would change a closed component's volume by more than
// denoise_flat_max_volume_change.
SelectedBumpDenoise denoise_selected_bump(const Points& input, const Points& lowpassed, const Triangles& triangles,
                                          const std::vector<int>& bump_faces, double bump_radius,
                                          const TransferFunction& g, const FilterOptions& options,
                                          const LowpassForBump& lowpass_for);

// The selected-bump path moves the surface along its normals only: bumps stand along them,
// and a lowpass at a bump's size, far coarser than the sampling, would drag vertices sideways
// by about that size. Noise that does not read along the normals also moved the vertices
// across the surface, and that path keeps it. This adds the sampling-noise rule's motion
// across the surface (`sampled` - `input`, less its part along the normals of `denoised`) to
// `denoised`: where the bump path took the noise along the normals, what the sampling rule
// would take across them goes too. On the tuning half's two patterned surfaces noised in
// random directions, 1.668e-3 -> 0.939e-3 and 2.016e-3 -> 0.759e-3 RMS from the truth (mean
// normal error 1.2 -> 1.1 and 2.5 -> 2.1 degrees). Noise along the normals has no such part:
// there the sampling rule moves along the normals only and nothing is added.
Points add_motion_across_surface(const Points& denoised, const Points& input, const Points& sampled,
                                 const Triangles& triangles);

// Per-vertex sampling noise with nothing selected. How much to smooth depends on the noise
// and on the mesh (its sampling, its sharp features), so no single cutoff serves every scan:
// measured on 16 noisy scans, the best fixed setting lost to MeshLab's default Laplacian
// smoothing on 7. Instead a few lowpasses are tried and the one with the lowest estimated
// risk (risk_estimate.h: the mean squared distance to the noise-free surface) is kept: the umbrella operator (per-vertex frequencies, in [0, 2],
// whatever the edge lengths: it follows irregular sampling) cut at these frequencies, and
// the intrinsic Delaunay cotangent operator (geometric: it follows the surface where the
// sampling is regular) cut at features of these radii in mean edge lengths h. Intrinsic
// Delaunay rather than the plain cotangent: at the same cutoffs it was as close to the truth
// or closer and folded fewer faces (bunny00 at 0.3 h: 6 against 15; docs/results.md section 4).
// The umbrella's two lowest cutoffs came with keeping only the motion along the normals: the
// sideways drift of a strong lowpass no longer costs, and 0.25, the lowest before, was chosen
// in 10 of the comparison's 22 cases.
constexpr double denoise_umbrella_cutoffs[] = {0.125, 0.18, 0.25, 0.35, 0.5, 0.7, 1.0, 1.4};
constexpr double denoise_cutoff_radii[] = {0.5, 0.75, 1.0, 1.5, 2.0};
// The risk estimate's probe (risk_estimate.h): 1 % of the mean edge length, its signs
// from a fixed seed, so that Denoise is deterministic and every candidate sees the same probe.
constexpr double denoise_probe_step = 0.01;
constexpr std::uint64_t denoise_probe_seed = 20261201;

// What Denoise runs on: a mesh, or a point cloud through its fans (the triangles each point
// makes with its neighbours in its tangent plane, overlapping one another), and the operator
// the user chose, if any. Automatically the candidates come from both families: the umbrella
// and a geometric one, the intrinsic Delaunay operator on a mesh and, on a cloud, the
// cloud's own cotangent operator (its fans are a soup that intrinsic flips cannot mend). On a
// cloud the noise is taken as along the normals, whatever its direction: a point's place along
// the surface is its sampling, which no smoother can tell from noise (on the cloud comparison's
// ten clouds the estimate said so anyway, noise in random directions included; on a uniformly
// random sphere cloud it read the sampling's irregularity as noise in every direction).
struct DenoiseSurface {
    std::optional<Operator> chosen;
    bool point_cloud = false;
};

// The lowpasses tried: both families unless an operator was chosen, else that operator's
// (the plain cotangent operator takes the same radii as the geometric family). Each family is
// consecutive, its cutoffs in increasing order.
std::vector<DenoiseDesign> denoise_sampling_candidates(double mean_edge_length, int order, const DenoiseSurface& surface);

// Within one operator the estimated risk of the lowpasses fell steadily to its lowest cutoff
// and rose steadily after it in every case measured (22 noisy scans, docs/results.md section 4;
// the cross-validation score used before behaved the same), so each family is searched
// downhill instead of scored whole: from its middle cutoff ((n - 1) / 2), the neighbours of the
// lowest score so far are scored until neither is lower. On those scans, with nine candidates
// then, this would score 158 of 198 and choose the same ones as scoring all.
// `score(i)` scores candidate i of [first, last); returns the indices scored, in that order.
std::vector<int> search_downhill(int first, int last, const std::function<double(int)>& score);

// Noise along the normals of standard deviation s moves a vertex across the surface by more
// than 3 s once in 370; where a lowpass moves one farther, it is reshaping the surface, not
// removing noise: on the comparison's diplodocus at 0.1 mean edge lengths the lowpass moved
// the toes' and the tail tip's vertices by up to 17 s and folded their faces.
constexpr double denoise_motion_bound_sigmas = 3.0;

// What Denoise makes of a lowpass's result on noisy points: when the noise looks along the
// normals, only the motion along them (normal_motion.h), no longer than
// denoise_motion_bound_sigmas standard deviations of the noise along them (`noise_sigma`, per vertex);
// when it looks along one direction (NoiseModel::AlongDirection), only the motion along that
// direction, bounded the same way; then each closed component given back its volume (volume.h: the lowpass shrinks thin
// curved parts). The candidates' risk is estimated on this, the surface Denoise returns, not
// on the lowpass alone: along the normals the two rank differently: ranking the lowpasses
// alone left Denoise 15-33 % farther from the truth on bunny00 at 0.3 and 0.5 mean edge
// lengths, the man at 0.3 and the diplodocus at 0.1 (noise along the normals;
// docs/results.md section 4).
// On a point cloud (`surface.point_cloud`, `triangles` its fans) the motion along the normals
// is kept at every point: the fans overlap and are no faces anyone sees, so a turned fan
// triangle folds nothing, while sending its points back kept the lowpass's sideways drift at
// 7,634 of the man cloud's 17,495 points (noise of 0.3 mean edge lengths along the normals:
// RMS to the clean points 1.46e-3 with the check, 1.31e-3 without; docs/results/clouds.md).
Points denoise_output(const Points& noisy, Points lowpassed, const Triangles& triangles, const DenoiseSurface& surface,
                      const NoiseDirection& noise, const Eigen::VectorXd& noise_sigma, NormalMotionReport* motion = nullptr, MotionBoundReport* bound = nullptr,
                      VolumeRestoreReport* volume = nullptr);

// On a large mesh the candidates are scored on patches of it, not on all of it: the risk is a
// mean over vertices, and the comparison's meshes, with 16k-44k vertices, chose the lowpass
// closest to the truth from that many. Above denoise_scoring_vertices vertices in faces,
// denoise_scoring_patches patches of denoise_scoring_vertices / denoise_scoring_patches
// vertices each, spread over the mesh (patches.h), are scored on their vertices at least
// denoise_scoring_margin rings inside them, where the free boundary at which a patch was cut
// out no longer reaches: on a sphere noised by s = 0.3 mean edge lengths, the widest-reaching
// candidates (the umbrella at 0.125, the intrinsic Delaunay operator at 2 h) differ there from
// their run on the whole mesh by at most 0.03 s (RMS 0.003 s); 10 rings in, by up to 0.28 s
// (unit test). The chosen lowpass then runs once on the whole mesh.
constexpr int denoise_scoring_vertices = 100000;
constexpr int denoise_scoring_patches = 8;
constexpr int denoise_scoring_margin = 20;

// Rounds of putting impulses back (noise_variance.h), the variance measured again after each.
// On the tuning half of experiments/generalize_denoise's scans with outliers, one round left
// 0.98-2.25e-3 RMS, three 0.32-0.80, eight and more 0.23-0.79 (none found after that).
constexpr int denoise_impulse_rounds = 20;

struct SamplingDenoise {
    Points points;         // the chosen lowpass applied to the input, its motion along the normals only
                           // when the noise looks so, closed components' volume restored
    DenoiseDesign design;  // the chosen lowpass
    FilterReport report;   // of the chosen lowpass's final run; seconds_total covers every candidate
    // Every candidate, with its score when the downhill search scored it.
    std::vector<std::pair<DenoiseDesign, std::optional<RiskEstimate>>> scores;
    // Per candidate: the most Lanczos steps a scoring run took (apply_filter takes the Lanczos
    // process for the umbrella's lowpasses), 0 when it was solved by factorisations (or not
    // scored at all).
    std::vector<int> krylov_steps;
    std::vector<double> scoring_seconds;  // per candidate, 0 when not scored
    // Where the time went: the noise's variance (impulse rounds included), its direction and
    // the scoring patches, the scoring, and the chosen lowpass's run with what follows it.
    struct Seconds {
        double variance = 0, direction = 0, scoring = 0, final_run = 0;
    } seconds;
    NoiseDirection noise;  // the noise model the scores assumed
    NoiseVariance variance;  // and the noise's variance they assumed
    // Impulses (noise_variance.h) put back on the mean of their neighbours before the rest: a
    // lowpass spreads a spike over its neighbours instead of removing it, and the motion
    // bound would hold it where it is.
    int impulses = 0;  // over every round
    // The fit to filtered normals (normal_fit.h) tried on the chosen lowpass, with its score,
    // and the strength kept (none when the mildest scored no lower than the lowpass alone).
    std::vector<std::pair<NormalFitStrength, RiskEstimate>> normal_fit_scores;
    std::optional<NormalFitStrength> normal_fit;
    std::optional<NormalMotionReport> normal_motion;  // when the noise looks along the normals
    std::optional<MotionBoundReport> motion_bound;    // likewise
    VolumeRestoreReport volume;
    int scored_vertices = 0;  // the vertices the risk was a mean over
    int scoring_patches = 0;  // 0: scored on the whole mesh, else on this many patches of it
    // The same estimate for leaving the mesh as it is: the noise itself, s^2 per noisy number
    // (residual 0, every noisy number passed through). When no lowpass scores below it, the
    // noise is smaller than what any of them would take of the surface's own shape, and
    // `points` is the input, untouched (design and report are then the best lowpass's, not run).
    double input_risk = 0;
    bool input_kept = false;
    // The mean over the vertices of the clean mesh's own reading subtracted from the noise's
    // variance (subtract_own_detail); 0 along one direction, where none is.
    double own_detail_variance = 0;
};

// Estimates the noise's direction and variance (noise_direction.h, noise_variance.h), then
// scores the candidates on the mesh by their estimated risk, each operator's family by
// search_downhill, each candidate twice: on the input and on the input perturbed by 1 % of the
// mean edge length, along the normals or on every axis as the noise looks (risk_estimate.h),
// each run finished by denoise_output. Applies the lowest-scoring one once more on its own
// (with options.tolerance) and finishes it the same way. Deterministic: the
// perturbation's signs come from a fixed seed. The runs solve to 1e-3 of the perturbation or
// to options.tolerance, whichever is tighter, so that solver error does not reach the
// scores. Scores on patches when the mesh has more than `score_on_patches_above` vertices in
// faces (see denoise_scoring_vertices, which it is but in tests; the patches then hold that
// many). Returns the input unchanged when leaving it scores lower than every lowpass
// (SamplingDenoise::input_risk). Throws Error like apply_filter.
SamplingDenoise denoise_sampling_noise(const Points& points, const Triangles& triangles, int order,
                                       const DenoiseSurface& surface, const FilterOptions& options,
                                       int score_on_patches_above = denoise_scoring_vertices);

// Denoise on a region: the blend band's width, in mean edge lengths, when blendWidth is auto.
// The sampling-noise rule has no feature radius. Its geometric candidates cut at radii of at
// most 2 mean edge lengths (denoise_cutoff_radii), so 3 spans the reach of any of them, and
// a fade across fewer vertices would be a step. Known before the candidates are scored, so a
// region Denoise cannot use is refused before the work.
constexpr double denoise_blend_edges = 3.0;
static_assert(denoise_blend_edges > denoise_cutoff_radii[std::size(denoise_cutoff_radii) - 1]);

} // namespace geofilter
