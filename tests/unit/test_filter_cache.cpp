// Reuse between runs (MeshLab's Preview): a cached run must meet the same tolerance as a
// fresh one, against the dense spectral filter, whatever was reused, including a factor
// held at a shift other than |r|.
#include "core/design/butterworth.h"
#include "core/solve/cascade.h"
#include "core/filter/filter.h"
#include "core/mesh/mesh_prep.h"
#include "core/solve/shifted_cholesky.h"
#include "core/solve/solvers.h"
#include "real_mesh.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace geofilter;
using namespace geofilter::reference;

namespace {

const Spectrum& patch_spectrum() {
    static const Spectrum spectrum = spectrum_of(man_scan_patch());
    return spectrum;
}

} // namespace

TEST(FilterCache, RunsOnTheSameMeshReuseAndStayWithinTolerance) {
    const Mesh& m = man_scan_patch();
    const Spectrum& spectrum = patch_spectrum();
    const double diag = bbox_diagonal(m.points);
    FilterCache cache;
    const std::vector<SecondOrderSpec> sequence = {
        {25, 50, 1, 1.1, 0}, {30, 60, 1, 1.1, 0}, {25, 60, 1, 3, 0.9}, {630, 1260, 1, 0.01, 1.1}, {25, 50, 1, 1.1, 0}};
    Points last;
    for (size_t k = 0; k < sequence.size(); ++k) {
        const TransferFunction g = design_second_order(sequence[k]);
        SCOPED_TRACE("run " + std::to_string(k));
        FilterReport report;
        const Points out = apply_filter(m.points, m.triangles, g, {}, &report, &cache);
        EXPECT_LE(area_weighted_rms(out - spectral_filter(spectrum, m.points, g), spectrum.mass), 1e-7 * diag);
        EXPECT_EQ(report.reused.empty(), k == 0);
        last = out;
    }
    FilterReport again;
    const Points repeated = apply_filter(m.points, m.triangles, design_second_order(sequence.back()), {}, &again, &cache);
    EXPECT_EQ(again.reused, "result");
    // The held result, bit for bit. (Not the first run's, though it asked for the same filter:
    // the last one's CG started from the run before it, and agrees with it to the tolerance.)
    EXPECT_TRUE(repeated == last);

    // Another mesh through the same cache starts afresh.
    Mesh moved = m;
    moved.points.col(0) *= 1.5;
    FilterReport other;
    const TransferFunction g = design_second_order(sequence[0]);
    const Points out = apply_filter(moved.points, moved.triangles, g, {}, &other, &cache);
    EXPECT_EQ(other.reused, "");
    const Spectrum moved_spectrum = spectrum_of(moved);
    EXPECT_LE(area_weighted_rms(out - spectral_filter(moved_spectrum, moved.points, g), moved_spectrum.mass),
              1e-7 * bbox_diagonal(moved.points));

    // A mesh larger than the cache's limit is filtered and not kept.
    FilterCache small(10);
    FilterReport uncached;
    apply_filter(m.points, m.triangles, g, {}, &uncached, &small);
    apply_filter(m.points, m.triangles, g, {}, &uncached, &small);
    EXPECT_EQ(uncached.reused, "");
}

TEST(FilterCache, AHeldFactorAtAnotherShiftStillMeetsTheTolerance) {
    const Mesh& m = man_scan_patch();
    const PreparedMesh prepared = prepare_mesh(m.points, m.triangles);
    ASSERT_EQ(prepared.points.rows(), m.points.rows());
    const Spectrum& spectrum = patch_spectrum();
    const Laplacian laplacian = cotan_laplacian(m.points, m.triangles);
    const double diag = bbox_diagonal(m.points);
    for (const SecondOrderSpec& spec : {SecondOrderSpec{25, 50, 1, 1.1, 0}, SecondOrderSpec{25, 60, 1, 3, 0.9}}) {
        const TransferFunction g = design_second_order(spec);
        const double ideal = std::abs(g.poles.at(0));
        for (double factor : {0.2, 5.0}) {
            SCOPED_TRACE("G1 = " + format_number(spec.G1) + ", held shift = " + format_number(factor) + " |r|");
            std::unique_ptr<detail::FactorState> state = std::make_unique<detail::FactorState>(laplacian);
            state->cholesky.factorize(factor * ideal);
            // Make a new factorisation look prohibitively expensive, so the held one is used.
            state->seconds_per_factorization = 1e9;
            state->seconds_per_pair_iteration = 1e-9;
            state->last_pair_iterations = 1;
            state->last_pair_rate = 0.5;
            FilterOptions options;
            FilterReport report;
            const Eigen::MatrixXd coordinates = m.points;
            detail::FilterProblem problem{laplacian, coordinates, g, options, diag};
            problem.factor_slot = &state;
            const Points out = detail::solve_factored(problem, report);
            EXPECT_EQ(state->cholesky.shift(), factor * ideal);  // no new factor was made
            EXPECT_GT(report.iterations, 0);
            EXPECT_LE(area_weighted_rms(out - spectral_filter(spectrum, m.points, g), spectrum.mass), 1e-7 * diag);
        }
    }
}

// A cached run's pair starts from the previous run's solution, rescaled: fewer CG iterations
// for a preview's parameter change, and the tolerance met whatever that start is (here also
// a random one, which the Galerkin scaling must not let make things worse than zero).
TEST(FilterCache, APairStartsFromThePreviousRunsSolution) {
    const Mesh& m = man_scan_patch();
    const Spectrum& spectrum = patch_spectrum();
    const Laplacian laplacian = cotan_laplacian(m.points, m.triangles);
    const double diag = bbox_diagonal(m.points);
    const Eigen::MatrixXd coordinates = m.points;
    const FilterOptions options;
    const auto run = [&](std::unique_ptr<detail::FactorState>& state, const TransferFunction& g, FilterReport& report) {
        detail::FilterProblem problem{laplacian, coordinates, g, options, diag};
        problem.factor_slot = &state;
        return Points(detail::solve_factored(problem, report));
    };
    const TransferFunction before = design_second_order({25, 50, 1, 1.1, 0});
    const TransferFunction after = design_second_order({27.5, 55, 1, 1.1, 0});

    std::unique_ptr<detail::FactorState> cold;
    FilterReport cold_report;
    run(cold, after, cold_report);

    std::unique_ptr<detail::FactorState> warm;
    FilterReport first, second;
    run(warm, before, first);
    ASSERT_EQ(warm->pair_solutions.size(), 1u);
    warm->cholesky.factorize(std::abs(after.poles.at(0)));  // the same preconditioner as the cold run
    const Points out = run(warm, after, second);
    EXPECT_LT(second.iterations, cold_report.iterations);
    EXPECT_LE(area_weighted_rms(out - spectral_filter(spectrum, m.points, after), spectrum.mass), 1e-7 * diag);

    warm->pair_solutions[0] = Eigen::MatrixXd::Random(m.points.rows(), 3);
    FilterReport third;
    const Points from_noise = run(warm, after, third);
    EXPECT_LE(area_weighted_rms(from_noise - spectral_filter(spectrum, m.points, after), spectrum.mass), 1e-7 * diag);
    EXPECT_LE(third.iterations, cold_report.iterations + 1);
}

// Other coordinates on the same triangles (Denoise's perturbed runs): the umbrella operator
// ignores positions, so the cache keeps its Laplacian and factor and redoes only what depends
// on the coordinates; the result is the fresh run's to the tolerance. The cotangent operator
// changes with the positions: rebuilt. (A lowpass with G(0) = 0.9, which also shrinks each
// component: one with G(0) = 1 on the umbrella takes the Lanczos process, no factor.)
TEST(FilterCache, TheUmbrellaOperatorServesMovedCoordinates) {
    const Mesh& m = man_scan_patch();
    const double diag = bbox_diagonal(m.points);
    Points moved = m.points;
    moved.col(2) += 0.01 * diag * moved.col(0).array().sin().matrix();
    TransferFunction g = design_butterworth_lowpass(0.5, 4);
    g.gain *= 0.9;
    FilterOptions umbrella;
    umbrella.op = Operator::Umbrella;
    FilterCache cache;
    FilterReport first, second, fresh;
    apply_filter(m.points, m.triangles, g, umbrella, &first, &cache);
    const Points rebound = apply_filter(moved, m.triangles, g, umbrella, &second, &cache);
    EXPECT_EQ(second.reused, "operator and factor");
    EXPECT_EQ(second.seconds_factorization, 0.0);
    const Points expected = apply_filter(moved, m.triangles, g, umbrella, &fresh);
    EXPECT_LE((rebound - expected).rowwise().norm().maxCoeff(), 1e-6 * diag);
    EXPECT_GT((rebound - moved).rowwise().norm().maxCoeff(), 1e-3 * diag);  // the filter did act

    FilterCache cotangent_cache;
    FilterReport cot_first, cot_second;
    const TransferFunction lowpass = design_second_order({25, 50, 1, 1.1, 0});
    apply_filter(m.points, m.triangles, lowpass, {}, &cot_first, &cotangent_cache);
    apply_filter(moved, m.triangles, lowpass, {}, &cot_second, &cotangent_cache);
    EXPECT_EQ(cot_second.reused, "");
}
