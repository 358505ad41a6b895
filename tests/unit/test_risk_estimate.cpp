// Denoise with nothing selected picks its lowpass by Stein's unbiased risk estimate with
// degrees of freedom measured by perturbation (core/denoise/risk_estimate.h) and the noise variance
// measured on the mesh (core/denoise/noise_variance.h). Checked against what they stand for: the
// degrees of freedom of a linear filter against the exact trace from a dense
// eigen-decomposition, the variance and the risk against the noise added and the distance to
// the clean mesh, and the chosen lowpass against the truth a user does not have (a clean real
// scan, noised along its normals or in every direction).
#include "core/denoise/denoise.h"
#include "core/denoise/noise_direction.h"
#include "core/denoise/noise_variance.h"
#include "core/denoise/risk_estimate.h"
#include "core/operators/operators.h"
#include "core/mesh/surface_measures.h"
#include "core/denoise/volume.h"
#include "real_mesh.h"
#include "run_filter.h"
#include "shapes.h"
#include "spectral.h"

#include "spectral.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

using namespace geofilter;

namespace {

using reference::rms_distance;

// The RMS distance to `clean` of the best of Denoise's candidates for mean edge length h,
// each applied whole to `noisy` (an oracle: what Denoise's own choice is measured against);
// with `best_points`, that candidate's result.
double best_candidate_applied_whole(const Points& noisy, const Triangles& triangles, const Points& clean, double h,
                                    Points* best_points = nullptr) {
    double best = INFINITY;
    FilterOptions options;
    for (const DenoiseDesign& d : denoise_sampling_candidates(h, 4, {})) {
        options.op = d.op;
        Points candidate = apply_filter(noisy, triangles, d.g, options);
        const double rms = rms_distance(candidate, clean);
        if (!(rms < best)) continue;
        best = rms;
        if (best_points) *best_points = std::move(candidate);
    }
    return best;
}


// Total standard deviation sigma, as the comparison's noise in random directions.
Points noised_in_every_direction(const Mesh& m, double sigma, unsigned seed) {
    std::mt19937 random(seed);
    std::normal_distribution<double> gauss(0.0, sigma / std::sqrt(3.0));
    Points out = m.points;
    for (Eigen::Index i = 0; i < out.rows(); ++i)
        for (int k = 0; k < 3; ++k) out(i, k) += gauss(random);
    return out;
}

} // namespace

// The umbrella operator does not depend on the positions, so its lowpass S is linear and the
// same on x, y and z: the expected degrees of freedom are tr S = sum_k G(lambda_k) over the
// eigenvalues of K v = lambda M v along unit normals, and 3 tr S in every direction.
TEST(RiskEstimate, DegreesOfFreedomOfALinearFilterAreItsTrace) {
    const Mesh m = icosphere(4, 1.0);  // 2,562 vertices
    const Laplacian l = umbrella_laplacian(m.triangles, m.points.rows());
    const Eigen::VectorXd eigenvalues =
        reference::generalized_eigenvalues(Eigen::MatrixXd(l.stiffness), Eigen::MatrixXd(l.mass.asDiagonal()));
    for (NoiseModel model : {NoiseModel::AlongNormals, NoiseModel::Isotropic})
        for (double cutoff : {0.3, 1.0}) {
            SCOPED_TRACE(noise_model_name(model));
            SCOPED_TRACE(cutoff);
            const TransferFunction g = design_butterworth_lowpass(cutoff, 4);
            double trace = 0;
            for (Eigen::Index k = 0; k < eigenvalues.size(); ++k)
                trace += g(std::max(0.0, eigenvalues[k]));
            if (model == NoiseModel::Isotropic) trace *= 3;
            FilterOptions options;
            options.op = Operator::Umbrella;
            options.tolerance = 1e-9;  // of the diagonal 2: far below the step 1e-4
            const Smoother smooth = [&](const Points& y) { return apply_filter(y, m.triangles, g, options); };
            // One probe's relative spread is about sqrt(2 / dof): average 16 (independent seeds).
            double mean = 0;
            const int probes = 16;
            for (int seed = 1; seed <= probes; ++seed)
                mean += estimate_risk(m.points, m.triangles, smooth, 1e-4, seed, {model}, Eigen::VectorXd::Zero(m.points.rows())).degrees_of_freedom /
                        probes;
            EXPECT_NEAR(mean, trace, 4 * std::sqrt(2 * trace / probes)) << "trace " << trace;
            EXPECT_GT(trace, 100);  // the bound above is then well under the trace itself
        }
}

// Given a smoother for the perturbed input, the estimate runs it on that input alone (on
// another thread, alongside the first on the input) and scores exactly as one smoother run
// twice in turn: two cotangent lowpasses with caches of their own, as Denoise runs them.
TEST(RiskEstimate, APerturbedRunAlongsideScoresAsTheRunsInTurn) {
    const Mesh m = icosphere(4, 1.0);
    const double h = mean_edge_length(m.points, m.triangles);
    const Points noisy = noised_along_normals(m, 0.3 * h, 5);
    const TransferFunction g = design_butterworth_lowpass(frequency_of_radius(1.5 * h), 4);
    FilterOptions options;
    options.op = Operator::IntrinsicDelaunay;
    const Eigen::VectorXd variance = Eigen::VectorXd::Constant(m.points.rows(), 0.09 * h * h);
    const Smoother in_turn = [&](const Points& y) { return apply_filter(y, m.triangles, g, options); };
    FilterCache on_input, on_perturbed;
    std::vector<double> first_coordinate;  // what each smoother was given
    double perturbed_coordinate = 0;
    const Smoother input_only = [&](const Points& y) {
        first_coordinate.push_back(y(0, 0));
        return apply_filter(y, m.triangles, g, options, nullptr, &on_input);
    };
    const Smoother perturbed_only = [&](const Points& y) {
        perturbed_coordinate = y(0, 0);
        return apply_filter(y, m.triangles, g, options, nullptr, &on_perturbed);
    };
    for (NoiseModel model : {NoiseModel::AlongNormals, NoiseModel::Isotropic}) {
        SCOPED_TRACE(noise_model_name(model));
        first_coordinate.clear();
        const RiskEstimate a = estimate_risk(noisy, m.triangles, in_turn, 0.01 * h, 3, {model}, variance);
        const RiskEstimate b = estimate_risk(noisy, m.triangles, input_only, 0.01 * h, 3, {model}, variance, nullptr, {}, {},
                                             perturbed_only);
        ASSERT_EQ(first_coordinate.size(), 1u);
        EXPECT_EQ(first_coordinate[0], noisy(0, 0));
        EXPECT_NE(perturbed_coordinate, noisy(0, 0));
        EXPECT_GT(a.degrees_of_freedom, 0.01 * a.observations);  // a lowpass that passes some noise
        EXPECT_NEAR(b.degrees_of_freedom, a.degrees_of_freedom, 1e-6 * a.observations);
        EXPECT_NEAR(b.risk, a.risk, 1e-9 * h * h);
        EXPECT_EQ(b.residual, a.residual);
    }
}

// The identity passes everything: its risk is the noise itself, s^2 per noisy number; a
// filter to the centroid passes nothing (dof 0), its risk the spread about the centroid less
// the noise the residual counted.
TEST(RiskEstimate, ExtremeSmoothersScoreAsTheFormulaSays) {
    const Mesh m = icosphere(2, 1.0);
    const Smoother identity = [](const Points& y) { return y; };
    const Eigen::VectorXd s2 = Eigen::VectorXd::Constant(m.points.rows(), 0.01);
    const RiskEstimate along = estimate_risk(m.points, m.triangles, identity, 1e-3, 1, {NoiseModel::AlongNormals}, s2);
    EXPECT_NEAR(along.degrees_of_freedom, m.points.rows(), 1e-6 * m.points.rows());
    EXPECT_EQ(along.observations, m.points.rows());
    EXPECT_NEAR(along.risk, 0.01, 1e-9);
    EXPECT_NEAR(along.unchanged, 0.01, 1e-15);
    const RiskEstimate every_way = estimate_risk(m.points, m.triangles, identity, 1e-3, 1, {NoiseModel::Isotropic}, s2);
    EXPECT_NEAR(every_way.degrees_of_freedom, 3 * m.points.rows(), 1e-6 * m.points.rows());
    EXPECT_EQ(every_way.observations, 3 * m.points.rows());
    EXPECT_NEAR(every_way.risk, 3 * 0.01, 1e-9);
    EXPECT_NEAR(every_way.unchanged, 3 * 0.01, 1e-15);
    const RiskEstimate collapse = estimate_risk(
        m.points, m.triangles, [](const Points& y) { return Points(Points::Zero(y.rows(), 3)); }, 1e-3, 1,
        {NoiseModel::AlongNormals}, s2);
    EXPECT_NEAR(collapse.degrees_of_freedom, 0, 1e-9);
    EXPECT_NEAR(collapse.residual, 1.0, 1e-12);  // unit sphere about the origin
    EXPECT_NEAR(collapse.risk, 1.0 - 0.01, 1e-12);
    // A finishing step changes the residual, not the degrees of freedom: the identity finished
    // by a collapse to the centroid passes all the noise and removes the whole sphere.
    const Finish to_centroid = [](const Points& y, const Points&) { return Points(Points::Zero(y.rows(), 3)); };
    const RiskEstimate finished =
        estimate_risk(m.points, m.triangles, identity, 1e-3, 1, {NoiseModel::AlongNormals}, s2, nullptr, to_centroid);
    EXPECT_NEAR(finished.degrees_of_freedom, m.points.rows(), 1e-6 * m.points.rows());
    EXPECT_NEAR(finished.residual, 1.0, 1e-12);
    EXPECT_NEAR(finished.risk, 1.0 + 0.01, 1e-12);
    EXPECT_THROW(estimate_risk(m.points, m.triangles, identity, 0, 1, {NoiseModel::AlongNormals}, s2), Error);
    EXPECT_THROW(estimate_risk(m.points, m.triangles, identity, 1e-3, 1, {NoiseModel::AlongNormals}, -s2), Error);
    EXPECT_THROW(estimate_risk(m.points, m.triangles, identity, 1e-3, 1, {NoiseModel::AlongNormals}, s2.head(3)), Error);
}

// On a sphere noised along its normals or in every direction, the variance estimated from the
// finest band is the noise's along the normals (measured on the noise actually added), and
// with it the risk estimate of a linear lowpass is its mean squared distance to the clean
// sphere, which only the test knows (to within the estimate's own spread).
// Detail of the clean mesh that reaches the finest band (here: one vertex in a hundred raised
// by six times the noise, like a scan's sharp edges and fingers) is not noise: the variance,
// a median over the vertices, stays within 10 % of the noise added along the normals (1.07),
// where the mean of the same squared residuals counts the detail too (1.35; checked above 1.2).
TEST(RiskEstimate, NoiseVarianceIgnoresASparseFineDetail) {
    const Mesh sphere = icosphere(5, 1.0);
    const double h = mean_edge_length(sphere.points, sphere.triangles);
    const Eigen::MatrixXd radial = vertex_normals(sphere.points, sphere.triangles);
    Mesh detailed = sphere;
    std::mt19937 random(4);
    std::vector<bool> raised(static_cast<std::size_t>(sphere.points.rows()), false);
    for (Eigen::Index i = 0; i < sphere.points.rows(); ++i)
        if (random() % 100 == 0) {
            raised[static_cast<std::size_t>(i)] = true;
            detailed.points.row(i) += 6 * 0.1 * h * radial.row(i);
        }
    const Points noisy = noised_along_normals(detailed, 0.1 * h, 7);
    const double added = ((noisy - detailed.points).cwiseProduct(radial)).rowwise().sum().squaredNorm() / sphere.points.rows();
    const NoiseVariance v = estimate_noise_variance(noisy, sphere.triangles, FilterOptions{});
    EXPECT_NEAR(v.mean / added, 1.0, 0.10);
    // What the mean would have said: the finest band's squared normal residuals, averaged.
    FilterOptions umbrella;
    umbrella.op = Operator::Umbrella;
    const Points band = noisy - apply_filter(noisy, sphere.triangles, design_butterworth_lowpass(1.0, 4), umbrella);
    const Eigen::MatrixXd normals = smoothed_vertex_normals(noisy, sphere.triangles);
    const double mean_squared = band.cwiseProduct(normals).rowwise().sum().squaredNorm() / sphere.points.rows();
    const double removed = 1 - 2 * v.degrees_of_freedom + v.kept;
    EXPECT_GT(mean_squared / removed / added, 1.2);
}

TEST(RiskEstimate, NoiseVarianceAndRiskMatchTheNoiseAndTheTruth) {
    const Mesh m = icosphere(5, 1.0);  // 10,242 vertices
    const double h = mean_edge_length(m.points, m.triangles);
    const Eigen::MatrixXd radial = vertex_normals(m.points, m.triangles);
    FilterOptions options;
    options.op = Operator::Umbrella;
    for (bool isotropic : {false, true})
        for (double level : {0.1, 0.3}) {
            SCOPED_TRACE(isotropic ? "in every direction" : "along the normals");
            SCOPED_TRACE(level);
            const Points noisy =
                isotropic ? noised_in_every_direction(m, level * h, 7) : noised_along_normals(m, level * h, 7);
            const double added = ((noisy - m.points).cwiseProduct(radial)).rowwise().sum().squaredNorm() / m.points.rows();
            const NoiseVariance v = estimate_noise_variance(noisy, m.triangles, FilterOptions{});
            EXPECT_NEAR(v.mean / added, 1.0, 0.05);
            // Half the finest band's noise passes (its cutoff is the middle of the umbrella's range).
            EXPECT_NEAR(v.degrees_of_freedom, 0.5, 0.05);
            for (double cutoff : {0.35, 0.7}) {
                SCOPED_TRACE(cutoff);
                const TransferFunction g = design_butterworth_lowpass(cutoff, 4);
                const Smoother smooth = [&](const Points& y) { return apply_filter(y, m.triangles, g, options); };
                Points smoothed;
                const RiskEstimate r = estimate_risk(noisy, m.triangles, smooth, 0.01 * h, 3,
                                                     {isotropic ? NoiseModel::Isotropic : NoiseModel::AlongNormals},
                                                     v.per_vertex, &smoothed);
                const double truth = (smoothed - m.points).rowwise().squaredNorm().mean();
                // Unbiased, with a spread of the noise's variance over ~sqrt(vertices): 1 % here.
                const double noise = (isotropic ? 3 : 1) * v.mean;
                EXPECT_NEAR(r.risk, truth, 0.05 * noise) << "risk " << r.risk << ", truth " << truth;
                EXPECT_LT(truth, 0.5 * noise);  // a real lowpass: the check above is not vacuous
            }
        }
}

// The downhill search scores the middle candidate, then the neighbours of the lowest score so
// far until neither is lower: on a valley it ends at the bottom, scoring fewer candidates the
// nearer the bottom lies to the middle; with two valleys it may end in the nearer one.
TEST(Denoise, SearchDownhillEndsAtTheBottomOfAValley) {
    for (int n = 1; n <= 6; ++n)
        for (int bottom = 0; bottom < n; ++bottom) {
            SCOPED_TRACE(n);
            SCOPED_TRACE(bottom);
            const int first = 3;  // any offset: the family's place in the candidate list
            const auto valley = [&](int i) { return std::abs(i - first - bottom) + 0.5 * (i - first); };
            const std::vector<int> order = search_downhill(first, first + n, valley);
            ASSERT_FALSE(order.empty());
            EXPECT_EQ(order.front(), first + (n - 1) / 2);
            const int lowest = *std::min_element(order.begin(), order.end(),
                                                 [&](int a, int b) { return valley(a) < valley(b); });
            EXPECT_EQ(lowest, first + bottom);
            EXPECT_EQ(std::set<int>(order.begin(), order.end()).size(), order.size()) << "a candidate scored twice";
            for (int i : order) {
                EXPECT_GE(i, first);
                EXPECT_LT(i, first + n);
            }
        }
    const auto count = [](int n, int bottom) {
        return search_downhill(0, n, [&](int i) { return std::abs(i - bottom); }).size();
    };
    EXPECT_EQ(count(5, 2), 3u);  // the middle and its two neighbours
    EXPECT_EQ(count(5, 0), 4u);  // 2, 1, 3, then 0
    EXPECT_EQ(count(4, 3), 4u);
    EXPECT_TRUE(search_downhill(2, 2, [](int) { return 0.0; }).empty());
    // Two valleys (bottoms at 2 and 4, the far one deeper): the search ends in the near one.
    const double two_valleys[] = {1, 2, 1.5, 3, 0};
    const std::vector<int> order = search_downhill(0, 5, [&](int i) { return two_valleys[i]; });
    EXPECT_EQ(std::count(order.begin(), order.end(), 4), 0);
}

// Denoise searches each operator's cutoffs downhill: every candidate it did not score, scored
// here on the same probe, scores no lower than the one it chose.
TEST(Denoise, CandidatesLeftUnscoredScoreNoLowerThanTheChosenOne) {
    const Mesh clean = icosphere(4, 1.0);
    const double h = mean_edge_length(clean.points, clean.triangles);
    for (bool isotropic : {false, true}) {
        SCOPED_TRACE(isotropic ? "in every direction" : "along the normals");
        const Points noisy = isotropic ? noised_in_every_direction(clean, 0.3 * h, 5) : noised_along_normals(clean, 0.3 * h, 5);
        FilterOptions options;
        std::vector<double> progress;
        options.progress = [&](double fraction, const std::string&) {
            progress.push_back(fraction);
            return true;
        };
        const SamplingDenoise out = denoise_sampling_noise(noisy, clean.triangles, 4, {}, options);
        // The bar only moves forward, across the scoring runs and the final one.
        ASSERT_FALSE(progress.empty());
        EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
        EXPECT_GE(progress.front(), 0.0);
        EXPECT_LE(progress.back(), 1.0);
        const double hn = mean_edge_length(noisy, clean.triangles);
        const double size = (noisy.colwise().maxCoeff() - noisy.colwise().minCoeff()).norm();
        double chosen = INFINITY;
        for (const auto& [design, score] : out.scores)
            if (design.origin == out.design.origin) chosen = score->risk;
        ASSERT_TRUE(std::isfinite(chosen));
        int unscored = 0;
        for (const auto& [design, score] : out.scores) {
            SCOPED_TRACE(design.origin);
            if (score) {
                EXPECT_GE(score->risk, chosen);
                continue;
            }
            ++unscored;
            FilterOptions o;
            o.op = design.op;
            o.tolerance = std::min(o.tolerance, 1e-3 * denoise_probe_step * hn / size);
            const Smoother smooth = [&](const Points& y) { return apply_filter(y, clean.triangles, design.g, o); };
            const Finish finish = [&](const Points& y, const Points& f) {
                return denoise_output(y, f, clean.triangles, {}, out.noise, out.variance.per_vertex.cwiseSqrt());
            };
            const double here = estimate_risk(noisy, clean.triangles, smooth, denoise_probe_step * hn,
                                              denoise_probe_seed, out.noise, out.variance.per_vertex,
                                              nullptr, finish)
                                    .risk;
            EXPECT_GE(here, chosen);
        }
        EXPECT_GT(unscored, 0) << "the search scored every candidate";
        if (isotropic) {
            // The result is the chosen lowpass run on its own (then fitted to its filtered normals
            // when that was kept, and given back its volume), bit for bit: it does not depend on
            // what the scoring runs before it held in their caches.
            FilterOptions o;
            o.op = out.design.op;
            Points lowpassed = apply_filter(noisy, clean.triangles, out.design.g, o);
            if (out.normal_fit) lowpassed = fit_to_filtered_normals(lowpassed, clean.triangles, faces_sharing_a_vertex(clean.triangles, clean.points.rows()),
                                                                    *out.normal_fit);
            const Points alone = restore_volume(noisy, lowpassed, clean.triangles);
            EXPECT_EQ((alone - out.points).cwiseAbs().maxCoeff(), 0.0);
        }
    }
}

// On a regular mesh, whose clean umbrella offsets are nearly all along the normals, the
// noise's direction shows in their split: Gaussian noise of standard deviation s on each
// axis it moves adds ~s^2 (1 + 1/6) to each squared component (noise_direction.h), so the
// tangential-over-normal ratio is near 0 for noise along the normals and near 2 for noise in
// every direction.
TEST(NoiseDirection, TellsNoiseAlongTheNormalsFromNoiseInEveryDirection) {
    const Mesh m = icosphere(5, 1.0);  // 10,242 vertices
    const double h = mean_edge_length(m.points, m.triangles);
    for (double level : {0.1, 0.3}) {
        SCOPED_TRACE(level);
        const NoiseDirection along =
            estimate_noise_direction(noised_along_normals(m, level * h, 5), m.triangles);
        EXPECT_EQ(along.model, NoiseModel::AlongNormals);
        EXPECT_LT(along.tangential_ratio, 0.3);
        const NoiseDirection every_way =
            estimate_noise_direction(noised_in_every_direction(m, level * h, 5), m.triangles);
        EXPECT_EQ(every_way.model, NoiseModel::Isotropic);
        EXPECT_GT(every_way.tangential_ratio, 2.0);
        EXPECT_LT(every_way.tangential_ratio, 3.0);
    }
}

// On a torus sampled 4x longer around its axis than around its tube, the long edges add the
// torus's curvature to the normal part of each umbrella offset: split there, noise in every
// direction read 1.93 (experiments/generalize_denoise's tori) and was taken as along the
// normals. The offset of the offsets cancels that smooth part. Read as along the normals, the
// risk leaves out the tangential two thirds of the noise and Denoise keeps the lightest
// lowpass: on the case families' tori, 1.7-2.1x Taubin's distance to the truth.
TEST(NoiseDirection, TellsTheDirectionOnATorusSampledLongerOneWay) {
    const Mesh m = torus(300, 30, 1.0, 0.4);
    const double h = mean_edge_length(m.points, m.triangles);
    for (double level : {0.3, 0.5}) {
        SCOPED_TRACE(level);
        const NoiseDirection along = estimate_noise_direction(noised_along_normals(m, level * h, 7), m.triangles);
        EXPECT_EQ(along.model, NoiseModel::AlongNormals) << along.tangential_ratio;
        const Points noisy = noised_in_every_direction(m, level * h, 7);
        const NoiseDirection every_way = estimate_noise_direction(noisy, m.triangles);
        EXPECT_EQ(every_way.model, NoiseModel::Isotropic) << every_way.tangential_ratio;
        // And Denoise ends near the best of its candidates, measured against the clean torus.
        const FilterSpec& spec = *find_filter("denoise");
        const RunOutput out = run_filter(spec, default_values(spec, false), {noisy, m.triangles, {}, {}});
        const double best = best_candidate_applied_whole(noisy, m.triangles, m.points, mean_edge_length(noisy, m.triangles));
        EXPECT_LE(rms_distance(out.points, m.points), 1.1 * best);
    }
}

// A depth scanner's noise: along one view direction everywhere, growing with depth. It is not
// along the normals, and where the view grazes the surface little of it shows along them: read
// as in every direction from its part along the normals, its variance came out a third to a
// half of the noise's on the generalization protocol's scans.
namespace {
Points noised_along_a_view(const Points& clean, const Eigen::Vector3d& view, double nearest, double farthest, unsigned seed,
                           Eigen::VectorXd* sigma) {
    const Eigen::VectorXd depth = clean * view;
    std::mt19937 random(seed);
    std::normal_distribution<double> gauss;
    Points noisy = clean;
    sigma->resize(clean.rows());
    for (Eigen::Index i = 0; i < noisy.rows(); ++i) {
        (*sigma)[i] = nearest + (farthest - nearest) * (depth[i] - depth.minCoeff()) / (depth.maxCoeff() - depth.minCoeff());
        noisy.row(i) += (*sigma)[i] * gauss(random) * view.transpose();
    }
    return noisy;
}
} // namespace

TEST(NoiseDirection, NoiseAlongOneViewDirectionIsReadAndMeasuredAlongIt) {
    const Mesh m = torus(160, 64, 1.0, 0.4);
    const double h = mean_edge_length(m.points, m.triangles);
    const Eigen::Vector3d view = Eigen::Vector3d(1, 2, 2).normalized();
    Eigen::VectorXd sigma;
    const Points noisy = noised_along_a_view(m.points, view, 0.1 * h, 0.5 * h, 17, &sigma);
    const NoiseDirection read = estimate_noise_direction(noisy, m.triangles);
    ASSERT_EQ(read.model, NoiseModel::AlongDirection) << read.tangential_ratio << " " << read.direction_share;
    EXPECT_GT(std::abs(read.direction.dot(view)), 0.99);
    const double added = sigma.squaredNorm() / static_cast<double>(sigma.size());
    const NoiseVariance along = estimate_noise_variance(noisy, m.triangles, FilterOptions{}, nullptr, read.direction);
    EXPECT_NEAR(along.mean / added, 1.0, 0.1);
    Eigen::Index deep, shallow;
    const Eigen::VectorXd depth = m.points * view;
    depth.maxCoeff(&deep);
    depth.minCoeff(&shallow);
    EXPECT_GT(along.per_vertex[deep], 9 * along.per_vertex[shallow]);  // 25x in the noise added
    const NoiseVariance across_the_surface = estimate_noise_variance(noisy, m.triangles, FilterOptions{});
    EXPECT_LT(across_the_surface.mean / added, 0.6);
    // Denoise on it: as close to the clean torus as the best of its candidates applied whole
    // (on this smooth, regular torus the lowpass drifts little along the surface).
    const FilterSpec& spec = *find_filter("denoise");
    const RunOutput out = run_filter(spec, default_values(spec, false), {noisy, m.triangles, {}, {}});
    const double best = best_candidate_applied_whole(noisy, m.triangles, m.points, h);
    EXPECT_LT(rms_distance(out.points, m.points), 1.05 * best);
    EXPECT_TRUE(std::any_of(out.log.begin(), out.log.end(), [](const std::string& line) {
        return line.rfind("noise model: along one direction", 0) == 0;
    }));
}

#ifdef GEOFILTER_MESHES
// On a scan, the lowpass drifts along the surface where its sampling is irregular: with the
// noise along one view direction, keeping only the lowpass's motion along it ends far closer
// to the clean bunny than any of the candidates applied whole (measured: 0.68x the best).
TEST(NoiseDirection, DenoiseRemovesADepthScannersNoiseAlongItsView) {
    const Mesh clean = reference::read_off(GEOFILTER_MESHES "/bunny00.off");
    const double h = mean_edge_length(clean.points, clean.triangles);
    Eigen::VectorXd sigma;
    const Points noisy = noised_along_a_view(clean.points, Eigen::Vector3d(1, 2, 2).normalized(), 0.1 * h, 0.5 * h, 11, &sigma);
    const FilterSpec& spec = *find_filter("denoise");
    const RunOutput out = run_filter(spec, default_values(spec, false), {noisy, clean.triangles, {}, {}});
    const double best = best_candidate_applied_whole(noisy, clean.triangles, clean.points, h);
    EXPECT_LT(rms_distance(out.points, clean.points), 0.8 * best);
}

// A CAD part's sharp edges: every lowpass that takes the noise off fandisk's flat sides also
// rounds its creases, and one that keeps them leaves the finest band's noise in the faces'
// normals. Fitted to its face normals smoothed edge-aware (normal_fit.h), Denoise ends closer
// to the clean part than the candidate closest to it applied whole, and turns the faces less
// than that candidate does (noise of 0.3 mean edge lengths in every direction).
TEST(RiskEstimate, DenoiseFitsACadPartToItsEdgeAwareNormals) {
    const Mesh clean = reference::read_off(GEOFILTER_MESHES "/fandisk_large.off");
    const double h = mean_edge_length(clean.points, clean.triangles);
    const Points noisy = noised_in_every_direction(clean, 0.3 * h, 5);
    const auto mean_turn = [&](const Points& p) { return reference::mean_normal_error_degrees(p, clean.points, clean.triangles); };
    Points best_points;
    const double best = best_candidate_applied_whole(noisy, clean.triangles, clean.points, h, &best_points);
    const double best_turn = mean_turn(best_points);
    const SamplingDenoise out = denoise_sampling_noise(noisy, clean.triangles, 4, {}, FilterOptions{});
    ASSERT_TRUE(out.normal_fit.has_value());
    EXPECT_LT(rms_distance(out.points, clean.points), best);
    EXPECT_LT(mean_turn(out.points), 0.8 * best_turn);
}

// Noise along a view direction: the fit to filtered normals squares the faces Denoise returns
// (the lowpass's motion along the view only), moving the vertices along the view. Against the
// same lowpass finished the same way without it, bunny00 ends closer to the clean scan and its
// faces turn less (measured: 0.77x the RMS, 0.58x the mean normal error).
TEST(NoiseDirection, DenoiseFitsADepthScanAlongItsView) {
    const Mesh clean = reference::read_off(GEOFILTER_MESHES "/bunny00.off");
    const double h = mean_edge_length(clean.points, clean.triangles);
    Eigen::VectorXd sigma;
    const Points noisy = noised_along_a_view(clean.points, Eigen::Vector3d(1, 2, 2).normalized(), 0.1 * h, 0.5 * h, 11, &sigma);
    const SamplingDenoise out = denoise_sampling_noise(noisy, clean.triangles, 4, {}, FilterOptions{});
    ASSERT_EQ(out.noise.model, NoiseModel::AlongDirection);
    ASSERT_TRUE(out.normal_fit.has_value());
    FilterOptions options;
    options.op = out.design.op;
    const Points unfitted = denoise_output(noisy, apply_filter(noisy, clean.triangles, out.design.g, options), clean.triangles,
                                           {}, out.noise, out.variance.per_vertex.cwiseSqrt());
    const auto mean_turn = [&](const Points& p) { return reference::mean_normal_error_degrees(p, clean.points, clean.triangles); };
    EXPECT_LT(rms_distance(out.points, clean.points), 0.9 * rms_distance(unfitted, clean.points));
    EXPECT_LT(mean_turn(out.points), 0.8 * mean_turn(unfitted));
}

// On real scans with noise along the normals or in every direction, the lowpass with the
// lowest estimated risk is within 10 % of the best candidate measured against the clean scan;
// run_filter returns that candidate and logs the choice and the noise model. At strong noise
// it is far better than the input (at 0.1 h none of the candidates beats the input on the man:
// docs/results.md section 4). The man (irregular) with noise along the normals and in every
// direction, where generalized cross-validation, the score used before, picked a lowpass 16 %
// off the best; bunny00 with noise in every direction, where an earlier score picked a
// cotangent smoother that keeps the tangential noise.
TEST(RiskEstimate, DenoisePicksNearlyTheBestCandidateAgainstTheTruth) {
    struct Case {
        const char* mesh;
        double level;
        bool isotropic;
        double of_input;  // the RMS error at most this fraction of the input's (0: not checked)
    };
    // In every direction on the man's irregular sampling no candidate removes the tangential
    // noise without pulling the vertices along the surface: the best is 0.79x the input
    // (docs/results.md section 4).
    for (const Case& c : {Case{"man", 0.1, false, 0}, Case{"man", 0.5, false, 0.7}, Case{"man", 0.3, true, 0.85},
                          Case{"bunny00", 0.3, true, 0.7}}) {
        SCOPED_TRACE(c.mesh);
        SCOPED_TRACE(c.level);
        SCOPED_TRACE(c.isotropic ? "in every direction" : "along the normals");
        const Mesh clean = reference::read_off((std::string(GEOFILTER_MESHES "/") + c.mesh + ".off").c_str());
        const double h = mean_edge_length(clean.points, clean.triangles);
        const Points noisy = c.isotropic ? noised_in_every_direction(clean, c.level * h, 11)
                                         : noised_along_normals(clean, c.level * h, 11);
        const FilterSpec& spec = *find_filter("denoise");
        const std::vector<int> none;
        const RunOutput out = run_filter(spec, default_values(spec, false), {noisy, clean.triangles, none, {}});
        const double chosen = rms_distance(out.points, clean.points);

        const double best = best_candidate_applied_whole(noisy, clean.triangles, clean.points, mean_edge_length(noisy, clean.triangles));
        EXPECT_LE(chosen, 1.1 * best);
        if (c.of_input > 0) EXPECT_LT(chosen, c.of_input * rms_distance(noisy, clean.points));
        // Noise along the normals: dropping the chosen lowpass's sideways drift (normal_motion.h)
        // brings the scan closer than the lowpass itself, both given back their volume.
        FilterOptions options;
        options.op = out.op;
        const Points lowpass = restore_volume(noisy, apply_filter(noisy, clean.triangles, out.transfer, options), clean.triangles);
        if (!c.isotropic) EXPECT_LT(chosen, 0.99 * rms_distance(lowpass, clean.points));
        bool logged_choice = false, logged_model = false, logged_projection = false;
        for (const auto& line : out.log) {
            logged_choice |= line.find("<- chosen") != std::string::npos;
            logged_model |= line.find(std::string("noise model: ") +
                                      (c.isotropic ? "in every direction" : "along the normals")) != std::string::npos;
            logged_projection |= line.find("motion along the normals only") != std::string::npos;
        }
        EXPECT_TRUE(logged_choice);
        EXPECT_TRUE(logged_model);
        EXPECT_EQ(logged_projection, !c.isotropic);
    }
}

// The fit to filtered normals refines a lowpass that takes noise off; it never overturns the
// reading that no lowpass beats leaving the mesh as it is. Fandisk with faint noise in every
// direction (0.001-0.003 mean edge lengths, a few draws): wherever no lowpass scored below
// leaving it, the part is left as it was and no fit was tried. Without that rule the
// fit scored below leaving it on a held-out draw like these and ended 14x farther from the
// clean part than its input.
TEST(RiskEstimate, TheNormalFitDoesNotOverturnLeavingANearlyCleanPart) {
    const Mesh clean = reference::read_off(GEOFILTER_MESHES "/fandisk_large.off");
    const double h = mean_edge_length(clean.points, clean.triangles);
    int left = 0;
    for (double level : {0.001, 0.002, 0.003})
        for (unsigned seed : {1u, 2u, 3u}) {
            SCOPED_TRACE(level);
            SCOPED_TRACE(seed);
            const Points noisy = noised_in_every_direction(clean, level * h, seed);
            const SamplingDenoise out = denoise_sampling_noise(noisy, clean.triangles, 4, {}, FilterOptions{});
            double lowpass = INFINITY;
            for (const auto& [design, score] : out.scores)
                if (score) lowpass = std::min(lowpass, score->risk);
            if (lowpass < out.input_risk) continue;
            ++left;
            EXPECT_TRUE(out.input_kept);  // run_filter then returns the input as it was
            EXPECT_TRUE(out.normal_fit_scores.empty());
        }
    EXPECT_GT(left, 0) << "no draw was faint enough to be left as it was";
}

// A clean scan reads as noise to the finest band alone: the curvature times irregular edge
// lengths varies from vertex to vertex (the clean man read 0.06 mean edge lengths, the clean
// fandisk 0.02). With the clean mesh's own reading subtracted (subtract_own_detail),
// Denoise finds no noise on them and returns them exactly; without it, it moved the man by
// 0.32e-3 RMS and folded 175 of its faces, and at noise of 0.02 edge lengths it ended 3x
// farther from the clean man than its input. Noise that is there is still read: 0.3 edge
// lengths along the normals of the man reads within 15 % of it.
TEST(RiskEstimate, DenoiseFindsNoNoiseOnACleanScan) {
    const FilterSpec& spec = *find_filter("denoise");
    for (const char* name : {"man", "fandisk_large"}) {
        SCOPED_TRACE(name);
        const Mesh clean = reference::read_off((std::string(GEOFILTER_MESHES "/") + name + ".off").c_str());
        const RunOutput out = run_filter(spec, default_values(spec, false), {clean.points, clean.triangles, {}, {}});
        EXPECT_EQ(out.points, clean.points);
        bool logged_unchanged = false;
        for (const auto& line : out.report.warnings) logged_unchanged |= line.find("left unchanged") != std::string::npos;
        EXPECT_TRUE(logged_unchanged);
    }
    const Mesh man = reference::read_off(GEOFILTER_MESHES "/man.off");
    const double h = mean_edge_length(man.points, man.triangles);
    const Points faint = noised_along_normals(man, 0.02 * h, 11);
    const RunOutput out = run_filter(spec, default_values(spec, false), {faint, man.triangles, {}, {}});
    EXPECT_LE(rms_distance(out.points, man.points), rms_distance(faint, man.points));
    const SamplingDenoise strong = denoise_sampling_noise(noised_along_normals(man, 0.3 * h, 11), man.triangles, 4, {}, {});
    EXPECT_NEAR(std::sqrt(strong.variance.mean), 0.3 * h, 0.15 * 0.3 * h);
    EXPECT_GT(strong.own_detail_variance, 0);
}
#endif

// A scan noisy on one half only: the most regular part of the whole mesh lies in the clean
// half, where the split's tangential part is the sampling's and its normal part nothing, so
// the noise read as in every direction and the lowpass's sideways pull slid the clean half's
// vertices. Read again where the noise is, it is along the normals, and the clean half stays
// nearly where it was.
#ifdef GEOFILTER_MESHES
TEST(NoiseDirection, NoiseOnHalfAScanIsReadWhereItIs) {
    const Mesh bunny = reference::read_off(GEOFILTER_MESHES "/bunny00.off");
    const double h = mean_edge_length(bunny.points, bunny.triangles);
    const Points loud = noised_along_normals(bunny, 0.4 * h, 23);
    const double middle = 0.5 * (bunny.points.col(0).minCoeff() + bunny.points.col(0).maxCoeff());
    Points noisy = bunny.points;
    std::vector<bool> quiet(static_cast<std::size_t>(bunny.points.rows()));
    for (Eigen::Index i = 0; i < noisy.rows(); ++i) {
        quiet[static_cast<std::size_t>(i)] = bunny.points(i, 0) < middle;
        if (!quiet[static_cast<std::size_t>(i)]) noisy.row(i) = loud.row(i);
    }
    const NoiseVariance variance = estimate_noise_variance(noisy, bunny.triangles, FilterOptions{});
    const NoiseDirection read = estimate_noise_direction(noisy, bunny.triangles, &variance.per_vertex);
    EXPECT_GT(read.tangential_ratio, 2.0);  // the premise: over the whole mesh it reads as in every direction
    EXPECT_EQ(read.model, NoiseModel::AlongNormals) << read.tangential_ratio_where_noisy;
    const FilterSpec& spec = *find_filter("denoise");
    const RunOutput out = run_filter(spec, default_values(spec, false), {noisy, bunny.triangles, {}, {}});
    double moved = 0;
    int count = 0;
    for (Eigen::Index i = 0; i < noisy.rows(); ++i)
        if (quiet[static_cast<std::size_t>(i)]) moved += (out.points.row(i) - bunny.points.row(i)).squaredNorm(), ++count;
    EXPECT_LT(std::sqrt(moved / count), 0.05 * h);
    EXPECT_LT(rms_distance(out.points, bunny.points), 0.5 * rms_distance(noisy, bunny.points));
}
#endif
