#include "core/denoise/denoise.h"
#include "core/denoise/base_detail.h"
#include "core/mesh/boundary.h"
#include "core/mesh/components.h"
#include "core/mesh/mesh_prep.h"
#include "core/operators/operators.h"
#include "core/denoise/patches.h"
#include "core/mesh/surface_measures.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace geofilter {

DenoiseDesign design_denoise_from_bump(const FeatureEllipsoid& bump, FeatureShape shape, int order, Operator op) {
    const double radius = denoise_radius_factor * bump.radius;
    const double cutoff = (shape == FeatureShape::Sphere ? 2.0 : 1.0) / (radius * radius);
    return {design_butterworth_lowpass(cutoff, order), op, cutoff,
            "the selected bump: cutoff radius " + format_number(radius) + " = " + format_number(denoise_radius_factor) +
                " x its radius " + format_number(bump.radius) +
                (shape == FeatureShape::Sphere ? " (sphere-like, s = 2/R^2)" : " (cylinder-like, s = 1/R^2)")};
}

bool denoise_bump_holds_boundary(const Triangles& triangles, Eigen::Index vertex_count) {
    const std::vector<bool> rim = boundary_vertices(triangles, vertex_count);
    return std::find(rim.begin(), rim.end(), true) != rim.end();
}

double selected_area_share(const Points& points, const Triangles& triangles, const std::vector<int>& faces) {
    double total = 0, selected = 0;
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) total += face_area(points, triangles, f);
    std::vector<bool> counted(static_cast<size_t>(triangles.rows()), false);
    for (int f : faces)
        if (f >= 0 && f < triangles.rows() && !counted[static_cast<size_t>(f)]) {
            counted[static_cast<size_t>(f)] = true;
            selected += face_area(points, triangles, f);
        }
    return total > 0 ? selected / total : 0.0;
}

namespace {

double detail_removed_at(const Points& input, const Points& lowpassed, const Triangles& triangles,
                         const std::vector<int>& faces) {
    const Eigen::MatrixXd normal = vertex_normals(lowpassed, triangles);
    Eigen::VectorXd area = Eigen::VectorXd::Zero(input.rows());
    for (int f : faces) {
        const double third = twice_area_normal(lowpassed, triangles, f).norm() / 6;
        for (int k = 0; k < 3; ++k) area[triangles(f, k)] += third;
    }
    const double total = area.sum();
    if (!(total > 0)) return 0;
    Eigen::VectorXd moved(input.rows());
    for (Eigen::Index v = 0; v < input.rows(); ++v) moved[v] = (input.row(v) - lowpassed.row(v)).dot(normal.row(v));
    const double mean = area.dot(moved) / total;
    return std::sqrt(area.dot((moved.array() - mean).square().matrix()) / total);
}

} // namespace

SelectedBumpDenoise denoise_selected_bump(const Points& input, const Points& lowpassed, const Triangles& triangles,
                                          const std::vector<int>& bump_faces, double bump_radius,
                                          const TransferFunction& g, const FilterOptions& options,
                                          const LowpassForBump& lowpass_for) {
    // What the lowpass kept of the bumps is computed by the same lowpass, on fields of unit
    // height: 1e-5 of the diagonal is far below what decides the fit.
    FilterOptions field_options = options;
    field_options.tolerance = std::max(options.tolerance, 1e-5);
    field_options.progress = nullptr;
    SelectedBumpDenoise out;
    out.points = remove_bump_pattern(input, lowpassed, triangles, bump_faces, bump_radius, g, field_options, &out.pattern);
    out.removed_detail = detail_removed_at(input, lowpassed, triangles, bump_faces);
    // A user's selection is a footprint, often wider than the bump (out to 1.6 radii in the
    // case families), and the lowpass cut for it takes part of what the bumps stand on into
    // what the fit has to explain. Where the profile fitted is narrower than the selection,
    // the pattern is fitted again under the lowpass cut for it, as the flat fallback is cut
    // (tuning half: a sphere's Gaussian pattern 0.583e-3 -> 0.534e-3 RMS, a torus's unchanged).
    out.pattern_radius = bump_radius;
    if (out.pattern.removed && out.pattern.width < bump_radius && lowpass_for) {
        const LowpassedForBump narrower = lowpass_for(input, out.pattern.width);
        BumpPatternReport again;
        Points refitted = remove_bump_pattern(input, narrower.points, triangles, bump_faces, out.pattern.width, narrower.g,
                                              field_options, &again);
        if (again.removed) {
            out.pattern_radius = out.pattern.width;
            out.points = std::move(refitted);
            out.pattern = again;
        }
    }
    if (out.pattern.removed) {
        out.outcome = SelectedBumpOutcome::PatternRemoved;
        if (lowpass_for) {
            // Tuning half, 12 cases that removed a pattern: the mean normal error from the truth
            // fell from 0.31-3.73 to 0.08-1.48 degrees, the RMS by 6-64 %, the volume moved by
            // at most 0.001 %.
            const double cut_as_bump = denoise_misfit_cut_factor / denoise_radius_factor * out.pattern_radius;
            const Points smoothed = keep_normal_motion(out.points, lowpass_for(out.points, cut_as_bump).points, triangles);
            VolumeRestoreReport volume;
            restore_volume(out.points, smoothed, triangles, &volume);
            out.misfit_volume_change = volume.largest_change;
            if (!(volume.closed_components > 0 && volume.largest_change > denoise_flat_max_volume_change)) {
                out.points = smoothed;
                out.misfit_lowpassed = true;
            }
        }
    } else if (out.removed_detail > bump_min_height * bump_radius) {
        // Bumps stand along the normals; the lowpass's sideways motion removes none of them and
        // moves a free boundary inwards. Faces turned by more than normal_motion_max_turn_degrees
        // still take the lowpass's positions: without that check the scans of the tuning half
        // of experiments/generalize_denoise folded 3-20x more faces.
        // The fitted width measures the bump itself; the selection, the user's footprint, was
        // up to twice as wide on the tuning half, and the lowpass cut for it took the base
        // surface's large bumps too (a sphere: 1.8x the input's RMS distance to the truth; cut
        // for the fitted width, 0.61x), so it is cut for the fitted width where that is narrower.
        // What the lowpass removed besides the bumps (the base's own detail at their size, its
        // level under a pattern of one sign) is put back (base_detail): on the tuning half's 21
        // noise-free flat fallbacks, 0.18-0.87 of the input's RMS distance to the truth (median
        // 0.42), where the lowpass cut at 1.5 times the selection and moved back to the base
        // level by a median offset ended 0.46-0.92 (median 0.69); lower in all 21.
        const bool for_fitted_width = out.pattern.width > 0 && out.pattern.width < bump_radius && lowpass_for;
        const Points narrower = for_fitted_width ? lowpass_for(input, out.pattern.width).points : Points();
        const Points& judged = for_fitted_width ? narrower : lowpassed;
        const Points flat = keep_normal_motion(input, judged, triangles);
        VolumeRestoreReport volume;
        restore_volume(input, flat, triangles, &volume);
        out.flat_volume_change = volume.largest_change;
        if (volume.closed_components > 0 && volume.largest_change > denoise_flat_max_volume_change) {
            out.outcome = SelectedBumpOutcome::Reshapes;
            out.points = input;
        } else {
            out.outcome = SelectedBumpOutcome::FlatLowpass;
            out.flat_for_fitted_width = for_fitted_width;
            out.flat_radius = for_fitted_width ? out.pattern.width : bump_radius;
            out.points = with_base_detail(input, flat, triangles, bump_faces, out.flat_radius, &out.base_detail);
        }
    } else {
        out.outcome = SelectedBumpOutcome::Unchanged;
        out.points = input;
    }
    return out;
}

Points add_motion_across_surface(const Points& denoised, const Points& input, const Points& sampled,
                                 const Triangles& triangles) {
    const Eigen::MatrixXd normal = vertex_normals(denoised, triangles);
    Points out = denoised;
    for (Eigen::Index v = 0; v < out.rows(); ++v) {
        const Eigen::RowVector3d moved = sampled.row(v) - input.row(v);
        out.row(v) += moved - moved.dot(normal.row(v)) * normal.row(v);
    }
    return out;
}

std::vector<DenoiseDesign> denoise_sampling_candidates(double mean_edge_length, int order, const DenoiseSurface& surface) {
    const std::optional<Operator>& op = surface.chosen;
    if (!(mean_edge_length > 0) || !std::isfinite(mean_edge_length))
        throw Error("the mesh has no edge of positive length");
    std::vector<DenoiseDesign> out;
    if (!op || *op == Operator::Umbrella)
        for (double sc : denoise_umbrella_cutoffs)
            out.push_back({design_butterworth_lowpass(sc, order), Operator::Umbrella, sc,
                           "per-vertex frequency " + format_number(sc) + " of the umbrella operator"});
    if (!op || *op != Operator::Umbrella)
        for (double k : denoise_cutoff_radii) {
            const double sc = frequency_of_radius(k * mean_edge_length);
            const Operator geometric = op ? *op : surface.point_cloud ? Operator::Cotangent : Operator::IntrinsicDelaunay;
            out.push_back({design_butterworth_lowpass(sc, order), geometric, sc,
                           "features of radius " + format_number(k) + " h = " + format_number(k * mean_edge_length) +
                               " (h the mean edge length), " + operator_name(geometric) + " operator"});
        }
    return out;
}

std::vector<int> search_downhill(int first, int last, const std::function<double(int)>& score) {
    if (first >= last) return {};
    std::vector<double> scores(static_cast<std::size_t>(last - first), 0);
    std::vector<bool> scored(scores.size(), false);
    std::vector<int> order;
    const auto at = [&](int i) {
        const auto k = static_cast<std::size_t>(i - first);
        if (!scored[k]) {
            scores[k] = score(i);
            scored[k] = true;
            order.push_back(i);
        }
        return scores[k];
    };
    int lowest = first + (last - first - 1) / 2;
    at(lowest);
    for (;;) {
        int next = lowest;
        for (int neighbour : {lowest - 1, lowest + 1})
            if (neighbour >= first && neighbour < last && at(neighbour) < at(next)) next = neighbour;
        if (next == lowest) return order;
        lowest = next;
    }
}

namespace {

// The noise moved each vertex along the one direction only, so its place across that
// direction is right: only the lowpass's motion along it is kept. `direction` is unit
// (NoiseDirection).
Points keep_motion_along(const Points& noisy, Points lowpassed, const Eigen::Vector3d& direction) {
    const Eigen::RowVector3d along = direction.transpose();
    for (Eigen::Index i = 0; i < lowpassed.rows(); ++i)
        lowpassed.row(i) = noisy.row(i) + (lowpassed.row(i) - noisy.row(i)).dot(along) * along;
    return lowpassed;
}

} // namespace

Points denoise_output(const Points& noisy, Points lowpassed, const Triangles& triangles, const DenoiseSurface& surface,
                      const NoiseDirection& noise, const Eigen::VectorXd& noise_sigma, NormalMotionReport* motion, MotionBoundReport* bound,
                      VolumeRestoreReport* volume) {
    if (noise.model == NoiseModel::AlongNormals) {
        lowpassed = keep_normal_motion(noisy, lowpassed, triangles, surface.point_cloud ? 180 : normal_motion_max_turn_degrees, motion);
        lowpassed = bound_motion(noisy, lowpassed, denoise_motion_bound_sigmas * noise_sigma, bound);
    } else if (noise.model == NoiseModel::AlongDirection) {
        lowpassed = keep_motion_along(noisy, lowpassed, noise.direction);
        lowpassed = bound_motion(noisy, lowpassed, denoise_motion_bound_sigmas * noise_sigma, bound);
    }
    return restore_volume(noisy, lowpassed, triangles, volume);
}

namespace {

// The fit to filtered normals on a lowpass's result. For noise along one direction, on that
// result as the model keeps it (its motion along the direction only) and moving the vertices
// along it: the faces it squares are then the ones Denoise returns. Fitted on the lowpass
// itself, whose sideways drift the model then drops, the faces it squared were the drifted
// ones: on the tuning half's man and diplodocus noised along a view direction 1.505e-3 RMS /
// 14.22 degrees and 0.413 / 2.93 from the truth, against 1.427 / 13.47 and 0.392 / 2.65.
// Along the normals the same order did worse (the fit was no longer kept on three of the
// tuning half's CAD parts: fandisk 1.095 / 4.52 back to 1.439 / 7.41), so there, as in every
// direction, the fit works on the lowpass.
Points fit_kept_motion(const Points& noisy, const Points& lowpassed, const Triangles& triangles,
                       const FaceNeighbourhoods& neighbourhoods, const NoiseDirection& noise, NormalFitStrength strength) {
    if (noise.model != NoiseModel::AlongDirection) return fit_to_filtered_normals(lowpassed, triangles, neighbourhoods, strength);
    return fit_to_filtered_normals(keep_motion_along(noisy, lowpassed, noise.direction), triangles, neighbourhoods, strength,
                                   &noise.direction);
}

} // namespace

SamplingDenoise denoise_sampling_noise(const Points& points, const Triangles& triangles, int order,
                                       const DenoiseSurface& surface, const FilterOptions& options,
                                       int score_on_patches_above) {
    const auto t0 = std::chrono::steady_clock::now();
    auto t_stage = t0;
    const auto stage_done = [&t_stage]() {
        const auto now = std::chrono::steady_clock::now();
        const double seconds = std::chrono::duration<double>(now - t_stage).count();
        t_stage = now;
        return seconds;
    };
    // Refuses a bad mesh (bad indices, NaN) with the filter's own message before measuring it.
    const PreparedMesh usable = prepare_mesh(points, triangles);
    const double h = mean_edge_length(usable.points, usable.triangles);
    const std::vector<DenoiseDesign> candidates = denoise_sampling_candidates(h, order, surface);
    const double step = denoise_probe_step * h;
    const double size = bounding_box_diagonal(points);

    SamplingDenoise best;
    // The variance of each noisy number: in every direction too, the noise along the normals
    // is one of three equal axes.
    // The umbrella runs of the noise estimate and, when it is the umbrella's, the final
    // lowpass share one mesh and operator, at any size.
    FilterCache umbrella(std::numeric_limits<Eigen::Index>::max());
    best.variance = estimate_noise_variance(points, triangles, options, &umbrella);
    Points y = points;
    // An impulse goes back to the mean of its neighbours: its neighbours are clean (it stands
    // out twice as far as any), while the finest band's lowpass keeps half of a spike. Impulses
    // near each other hide one another: measured again once those found are back, until none
    // is left.
    const VertexNeighbours neighbours = vertex_neighbours(triangles, points.rows());
    for (int round = 0; round < denoise_impulse_rounds && !best.variance.impulses.empty(); ++round) {
        const Points before = y;
        for (int i : best.variance.impulses) {
            Eigen::RowVector3d mean = Eigen::RowVector3d::Zero();
            for (int j = neighbours.start[i]; j < neighbours.start[i + 1]; ++j) mean += before.row(neighbours.index[j]);
            y.row(i) = mean / (neighbours.start[i + 1] - neighbours.start[i]);
        }
        best.impulses += static_cast<int>(best.variance.impulses.size());
        best.variance = estimate_noise_variance(y, triangles, options, &umbrella);
    }
    best.seconds.variance = stage_done();
    Points usable_y = usable.points;
    for (Eigen::Index k = 0; k < usable_y.rows(); ++k) usable_y.row(k) = y.row(usable.active_vertex[static_cast<std::size_t>(k)]);
    // A cloud's place along the surface is its sampling (DenoiseSurface).
    if (surface.point_cloud) {
        best.noise.model = NoiseModel::AlongNormals;
    } else {
        Eigen::VectorXd usable_variance(usable_y.rows());
        for (Eigen::Index k = 0; k < usable_y.rows(); ++k)
            usable_variance[k] = best.variance.per_vertex[usable.active_vertex[static_cast<std::size_t>(k)]];
        best.noise = estimate_noise_direction(usable_y, usable.triangles, &usable_variance);
    }
    // Noise along one direction is measured along it: along the normals a vertex whose surface
    // that direction grazes shows little of it.
    // Otherwise the clean mesh's own reading is taken out of it (subtract_own_detail: not along
    // one direction, where the smoothed mesh keeps the noise's sideways part).
    if (best.noise.model == NoiseModel::AlongDirection)
        best.variance = estimate_noise_variance(y, triangles, options, &umbrella, best.noise.direction);
    else
        best.own_detail_variance = subtract_own_detail(best.variance, y, triangles, order, options, &umbrella);
    const Eigen::VectorXd sigma = best.variance.per_vertex.cwiseSqrt();
    for (const DenoiseDesign& design : candidates) best.scores.emplace_back(design, std::nullopt);
    best.krylov_steps.assign(candidates.size(), 0);
    best.scoring_seconds.assign(candidates.size(), 0);
    // What the candidates are scored on: the mesh, or patches of a large one.
    ScoringPatches patches;
    if (usable.points.rows() > score_on_patches_above) {
        patches = scoring_patches(usable.triangles, usable_y, denoise_scoring_patches,
                                  score_on_patches_above / denoise_scoring_patches, denoise_scoring_margin);
        best.scoring_patches = patches.patches;
    }
    best.seconds.direction = stage_done();
    const Points& scored_points = best.scoring_patches ? patches.mesh.points : y;
    Eigen::VectorXd scored_variance = best.variance.per_vertex;
    if (best.scoring_patches) {
        scored_variance.resize(static_cast<Eigen::Index>(patches.mesh.vertex.size()));
        for (std::size_t k = 0; k < patches.mesh.vertex.size(); ++k)
            scored_variance[static_cast<Eigen::Index>(k)] =
                best.variance.per_vertex[usable.active_vertex[static_cast<std::size_t>(patches.mesh.vertex[k])]];
    }
    const Eigen::VectorXd scored_sigma = scored_variance.cwiseSqrt();
    const Triangles& scored_triangles = best.scoring_patches ? patches.mesh.triangles : triangles;
    int chosen = -1;
    // The last scoring runs' lowpassed input and perturbed input, and the chosen candidate's:
    // the fit to filtered normals is scored on the chosen lowpass's runs without running it again.
    Points lowpassed[2], chosen_lowpassed[2];
    // Progress: the scoring runs share the first 90 % (counted as if every candidate were
    // scored: the search skips some, so the bar jumps ahead at the end), the final run the rest.
    const double scoring_share = 0.9;
    const int runs = 2 * static_cast<int>(candidates.size());
    int run = 0;
    // The runs on the input and on the perturbed input each keep their mesh for the next
    // candidate of the same operator. The umbrella ignores the positions, so its perturbed
    // runs share the input's cache (FilterCache rebinds the coordinates): the same factor,
    // and CG starting from the input run's solution, a probe step away.
    FilterCache on_input, on_perturbed;
    const auto score_candidate = [&](int index) {
        const DenoiseDesign& design = candidates[static_cast<std::size_t>(index)];
        FilterOptions o = options;
        o.op = design.op;
        o.tolerance = std::min(options.tolerance, 1e-3 * step / size);
        const auto t_candidate = std::chrono::steady_clock::now();
        // An operator built from the positions gives the perturbed run a cache of its own. That
        // run then goes on another thread alongside the input's (estimate_risk), unless an
        // external solver runs the solves (geofilter-mpi's, collective over its ranks: one solve
        // at a time). Going alongside, it reports no progress (a front end's progress bar
        // belongs to the thread that called it), and both runs solve every pair by CG: an exact
        // pair's factorisation (MUMPS) is not made from two threads at once. A Butterworth
        // lowpass of order 3 or more never takes one anyway (exact_pair.h).
        const bool own_cache = operator_uses_positions(design.op);
        const bool alongside = own_cache && !options.external_solver;
        if (alongside) o.complex_factorization = nullptr;
        const int base = run;
        int krylov_steps[2] = {0, 0};
        const auto filter_run = [&](const Points& at, bool perturbed) {
            FilterOptions mine = o;
            mine.progress = nullptr;
            if (options.progress && !(perturbed && alongside))
                mine.progress = [&, perturbed](double fraction, const std::string& stage) {
                    return options.progress(scoring_share * (base + (perturbed ? 1 : 0) + fraction) / runs,
                                            "Denoise: " + design.origin + (perturbed ? " (perturbed)" : "") + ": " + stage);
                };
            FilterReport report;
            Points out = apply_filter(at, scored_triangles, design.g, mine, &report, perturbed && own_cache ? &on_perturbed : &on_input);
            krylov_steps[perturbed ? 1 : 0] = report.krylov_steps;
            lowpassed[perturbed ? 1 : 0] = out;
            return out;
        };
        int calls = 0;
        const Smoother smooth = [&](const Points& at) { return filter_run(at, calls++ == 1); };
        const Smoother smooth_perturbed =
            alongside ? Smoother([&](const Points& at) { return filter_run(at, true); }) : Smoother();
        const RiskEstimate score = estimate_risk(
            scored_points, scored_triangles, smooth, step, denoise_probe_seed, best.noise, scored_variance, nullptr,
            [&](const Points& at, const Points& f) { return denoise_output(at, f, scored_triangles, surface, best.noise, scored_sigma); },
            patches.counted, smooth_perturbed);
        run += 2;
        best.krylov_steps[static_cast<std::size_t>(index)] = std::max(krylov_steps[0], krylov_steps[1]);
        best.scoring_seconds[static_cast<std::size_t>(index)] =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t_candidate).count();
        best.scores[static_cast<std::size_t>(index)].second = score;
        best.scored_vertices = score.vertices;
        if (chosen < 0 || score.risk < best.scores[static_cast<std::size_t>(chosen)].second->risk) {
            chosen = index;
            chosen_lowpassed[0].swap(lowpassed[0]);
            chosen_lowpassed[1].swap(lowpassed[1]);
        }
        return score.risk;
    };
    for (std::size_t first = 0; first < candidates.size();) {
        std::size_t last = first;
        while (last < candidates.size() && candidates[last].op == candidates[first].op) ++last;
        on_input.clear();
        on_perturbed.clear();
        search_downhill(static_cast<int>(first), static_cast<int>(last), score_candidate);
        first = last;
    }
    best.design = candidates.at(static_cast<std::size_t>(chosen));
    // The fit to filtered normals on top of the chosen lowpass, scored as the lowpass was (its
    // runs on the input and the perturbed input, each fitted): from the mildest strength up,
    // while each scores below the last. Not on a cloud, whose fans overlap and have no faces
    // to stand square to anything; and only when the lowpass itself scored below leaving the
    // mesh as it is: the fit refines a lowpass that takes noise off, it does not overturn the
    // reading that there is none worth taking. On a held-out fandisk with next to no noise
    // (0.0025 mean edge lengths RMS) the lowpass scored 0.3 % above leaving it, the fit below, and
    // the fitted part ended 14x farther from the clean one than its input.
    double lowest_risk = best.scores[static_cast<std::size_t>(chosen)].second->risk;
    FaceNeighbourhoods scored_neighbourhoods;
    if (!surface.point_cloud && lowest_risk < best.scores[static_cast<std::size_t>(chosen)].second->unchanged) {
        scored_neighbourhoods = faces_sharing_a_vertex(scored_triangles, scored_points.rows());
        for (const NormalFitStrength& strength : normal_fit_strengths) {
            int calls = 0;
            const Smoother fitted = [&](const Points& at) {
                return fit_kept_motion(at, chosen_lowpassed[calls++ == 0 ? 0 : 1], scored_triangles, scored_neighbourhoods,
                                       best.noise, strength);
            };
            const RiskEstimate score = estimate_risk(
                scored_points, scored_triangles, fitted, step, denoise_probe_seed, best.noise, scored_variance, nullptr,
                [&](const Points& at, const Points& f) { return denoise_output(at, f, scored_triangles, surface, best.noise, scored_sigma); },
                patches.counted);
            best.normal_fit_scores.emplace_back(strength, score);
            if (!(score.risk < lowest_risk)) break;
            lowest_risk = score.risk;
            best.normal_fit = strength;
        }
    }
    best.seconds.scoring = stage_done();
    // Leaving the mesh as it is passes every noisy number, so its risk is the noise's own.
    // Measured where it matters: the man with noise of 0.1 mean edge lengths in random
    // directions, where every lowpass ends farther from the truth than the input (0.561e-3
    // RMS in, 0.731e-3 for the best-scoring lowpass), and the estimate says so.
    best.input_risk = best.scores[static_cast<std::size_t>(chosen)].second->unchanged;
    if (!(lowest_risk < best.input_risk)) {
        best.input_kept = true;
        best.points = y;
        best.report.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return best;
    }
    // A scoring run that follows another holds that run's factor or makes a new one as their
    // measured times say, which moves its result within the tolerance; the chosen lowpass is
    // applied once more on its own, so that the result depends on the mesh and the choice
    // only, not on the order the search scored the candidates in or on the machine's load.
    FilterOptions o = options;
    o.op = best.design.op;
    if (options.progress)
        o.progress = [&](double fraction, const std::string& stage) {
            return options.progress(scoring_share + (1 - scoring_share) * fraction,
                                    "Denoise: the chosen lowpass, " + best.design.origin + ": " + stage);
        };
    if (best.noise.model == NoiseModel::AlongNormals) best.normal_motion.emplace();
    if (best.noise.model != NoiseModel::Isotropic) best.motion_bound.emplace();
    Points lowpassed_y = apply_filter(y, triangles, best.design.g, o, &best.report, best.design.op == Operator::Umbrella ? &umbrella : nullptr);
    if (best.normal_fit) {
        // Made for the scored mesh, which is the whole mesh unless it was scored on patches.
        if (best.scoring_patches) scored_neighbourhoods = faces_sharing_a_vertex(triangles, y.rows());
        lowpassed_y = fit_kept_motion(y, lowpassed_y, triangles, scored_neighbourhoods, best.noise, *best.normal_fit);
    }
    best.points = denoise_output(y, std::move(lowpassed_y), triangles, surface,
                                 best.noise, sigma, best.normal_motion ? &*best.normal_motion : nullptr,
                                 best.motion_bound ? &*best.motion_bound : nullptr, &best.volume);
    best.seconds.final_run = stage_done();
    best.report.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return best;
}

} // namespace geofilter
