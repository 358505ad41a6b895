// bound_motion and its use by Denoise: a vertex the lowpass would move farther than the
// noise could have displaced it moves exactly that far, along the same direction; every
// other vertex keeps the lowpass's motion.
#include "core/denoise/denoise.h"
#include "core/denoise/motion_bound.h"
#include "core/mesh/surface_measures.h"
#include "shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace geofilter;

TEST(BoundMotion, ShortensOnlyTheLongerMotionsAlongTheirOwnDirection) {
    Points input(4, 3), moved(4, 3);
    input << 0, 0, 0, 1, 1, 1, -2, 0, 5, 3, 3, 3;
    moved = input;
    moved.row(0) += Eigen::RowVector3d(0.3, 0.4, 0.0);   // length 0.5: within the bound
    moved.row(1) += Eigen::RowVector3d(0.0, 0.0, -2.0);  // length 2: to 1 along -z
    moved.row(2) += Eigen::RowVector3d(3.0, 4.0, 12.0);  // length 13: to 1 along (3, 4, 12) / 13
    MotionBoundReport report;
    const Points out = bound_motion(input, moved, Eigen::VectorXd::Ones(4), &report);
    EXPECT_EQ(report.vertices_held, 2);
    EXPECT_DOUBLE_EQ(report.bound, 1.0);
    EXPECT_EQ(out.row(0), moved.row(0));
    EXPECT_EQ(out.row(3), input.row(3));
    EXPECT_NEAR((out.row(1) - Eigen::RowVector3d(1, 1, 0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((out.row(2) - Eigen::RowVector3d(-2 + 3.0 / 13, 4.0 / 13, 5 + 12.0 / 13)).norm(), 0.0, 1e-15);
}

// The unit icosphere of 2,562 vertices noised along its normals by 0.2 mean edge lengths.
struct NoisySphere {
    Mesh clean;
    double sigma;
    Points noisy;
};
NoisySphere noisy_sphere() {
    NoisySphere s{icosphere(4, 1.0), 0, {}};
    s.sigma = 0.2 * mean_edge_length(s.clean.points, s.clean.triangles);
    const Eigen::MatrixXd n = vertex_normals(s.clean.points, s.clean.triangles);
    std::mt19937 random(3);
    std::normal_distribution<double> gauss(0.0, s.sigma);
    s.noisy = s.clean.points;
    for (Eigen::Index v = 0; v < s.noisy.rows(); ++v) s.noisy.row(v) += gauss(random) * n.row(v);
    return s;
}

// A sphere noised along its normals with a narrow feature standing 12 noise deviations out of
// it: a vertex and its ring raised together (narrower than any cutoff the noise calls for,
// like a toe or a tail's tip). The lowpass Denoise chooses flattens it, but no vertex moves
// farther than 3 deviations of the noise Denoise measured there (plus the uniform offset that
// gives the volume back), so the feature stays at least 9 deviations high. Its vertices stand
// out together, so none is taken for an impulse.
TEST(BoundMotion, DenoiseMovesNoVertexFartherThanThreeDeviationsOfTheNoise) {
    const NoisySphere s = noisy_sphere();
    const Mesh& clean = s.clean;
    const double sigma = s.sigma;
    Points noisy = s.noisy;
    const Eigen::Index tip = 0;
    std::vector<bool> feature(static_cast<std::size_t>(noisy.rows()), false);
    for (Eigen::Index f = 0; f < clean.triangles.rows(); ++f)
        for (int k = 0; k < 3; ++k)
            if (clean.triangles(f, k) == tip)
                for (int j = 0; j < 3; ++j) feature[static_cast<std::size_t>(clean.triangles(f, j))] = true;
    for (Eigen::Index v = 0; v < noisy.rows(); ++v)
        if (feature[static_cast<std::size_t>(v)]) noisy.row(v) = clean.points.row(v) * (1 + 12 * sigma);

    const SamplingDenoise out = denoise_sampling_noise(noisy, clean.triangles, 4, {}, FilterOptions{});
    ASSERT_EQ(out.noise.model, NoiseModel::AlongNormals);
    ASSERT_TRUE(out.motion_bound);
    EXPECT_EQ(out.impulses, 0);
    const double measured = std::sqrt(out.variance.mean);
    EXPECT_NEAR(measured, sigma, 0.25 * sigma);
    EXPECT_GE(out.motion_bound->vertices_held, 1);
    const double slack = out.volume.largest_offset + 1e-12;
    for (Eigen::Index v = 0; v < noisy.rows(); ++v)
        EXPECT_LE((out.points.row(v) - noisy.row(v)).norm(),
                  denoise_motion_bound_sigmas * std::sqrt(out.variance.per_vertex[v]) + slack) << "vertex " << v;
    EXPECT_GE(out.points.row(tip).norm() - 1, (12 - denoise_motion_bound_sigmas) * sigma - 0.25 * 3 * sigma - slack);
    // The rest of the sphere is still denoised: closer to the clean sphere than the input.
    Eigen::VectorXd off_input(noisy.rows()), off_output(noisy.rows());
    for (Eigen::Index v = 0; v < noisy.rows(); ++v) {
        const bool raised = feature[static_cast<std::size_t>(v)];
        off_input[v] = raised ? 0 : std::abs(noisy.row(v).norm() - 1);
        off_output[v] = raised ? 0 : std::abs(out.points.row(v).norm() - 1);
    }
    EXPECT_LT(off_output.norm(), 0.6 * off_input.norm());
}

// A spike of one vertex, 12 deviations out, its neighbours at the noise's level: no surface
// makes that, it is an outlier of the scan. Denoise puts it back on the mean of its neighbours
// before it smooths (which would spread it, and the motion bound hold it), and the spike
// ends within the noise of the clean sphere. Noise alone throws no vertex that far.
TEST(BoundMotion, DenoisePutsAnImpulseBackInsteadOfHoldingIt) {
    const NoisySphere s = noisy_sphere();
    const Mesh& clean = s.clean;
    const double sigma = s.sigma;
    Points noisy = s.noisy;
    const SamplingDenoise quiet = denoise_sampling_noise(noisy, clean.triangles, 4, {}, FilterOptions{});
    EXPECT_EQ(quiet.impulses, 0);
    const Eigen::Index spike = 0;
    noisy.row(spike) = clean.points.row(spike) * (1 + 12 * sigma);
    const SamplingDenoise out = denoise_sampling_noise(noisy, clean.triangles, 4, {}, FilterOptions{});
    EXPECT_EQ(out.impulses, 1);
    EXPECT_TRUE(out.variance.impulses.empty());  // measured again with the spike back: none left
    EXPECT_LT(std::abs(out.points.row(spike).norm() - 1), 3 * sigma);
    EXPECT_GT(std::abs(quiet.points.row(spike).norm() - 1) + 9 * sigma, std::abs(out.points.row(spike).norm() - 1));
}

// Two spikes side by side, 12 deviations out, one up and one down: each is the other's
// loudest neighbour, so neither stands out twice as far as every neighbour, and putting
// impulses back round after round would never reveal either. Each stands out alone but for
// the other, so both are put back. (Two spikes of the same sign side by side are a bump of two
// vertices to the lowpass: their common neighbours take more than half of their residual, and
// such a pair is left to it.)
TEST(BoundMotion, DenoisePutsBackTwoImpulsesSideBySide) {
    const NoisySphere s = noisy_sphere();
    const Mesh& clean = s.clean;
    const double sigma = s.sigma;
    const Eigen::Index first = clean.triangles(0, 0), second = clean.triangles(0, 1);
    Points noisy = s.noisy;
    noisy.row(first) = clean.points.row(first) * (1 + 12 * sigma);
    noisy.row(second) = clean.points.row(second) * (1 - 12 * sigma);
    const SamplingDenoise out = denoise_sampling_noise(noisy, clean.triangles, 4, {}, FilterOptions{});
    EXPECT_EQ(out.impulses, 2);
    for (const Eigen::Index spike : {first, second})
        EXPECT_LT(std::abs(out.points.row(spike).norm() - 1), 3 * sigma) << "spike " << spike;
}
