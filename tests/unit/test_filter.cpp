#include "core/filter/filter.h"
#include "filter_table.h"
#include "spectral.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace geofilter;
using namespace geofilter::reference;

namespace {

// ~1,000 vertices with content at every frequency: a noisy torus.
Mesh test_mesh() {
    Mesh m = torus(40, 25, 1.0, 0.35);
    perturb_radially(m, 0.02, 11);
    return m;
}

const Spectrum& test_spectrum() {
    static const Spectrum s = spectrum_of(test_mesh());
    return s;
}

std::vector<SecondOrderSpec> preset_specs() {
    std::vector<SecondOrderSpec> out;
    for (const auto& f : filter_table()) {
        if (f.kind != FilterKind::SecondOrder) continue;
        out.push_back(f.reference);
    }
    // Paper sets whose frequencies matter on a mesh of unit size, sharp and wide ones.
    out.push_back({10, 25, 1, 30, 0});
    out.push_back({20, 25, 1, 2, 0.9});
    out.push_back({200, 1000, 0.5, 1.1, 0});
    return out;
}

void expect_matches_spectral(Solver solver, double tolerance) {
    const Mesh m = test_mesh();
    const double diag = bbox_diagonal(m.points);
    for (const auto& spec : preset_specs()) {
        SCOPED_TRACE("s1=" + std::to_string(spec.s1) + " s2=" + std::to_string(spec.s2) + " G1=" + std::to_string(spec.G1));
        const TransferFunction g = design_second_order(spec);
        FilterOptions options;
        options.solver = solver;
        options.tolerance = tolerance;
        FilterReport report;
        const Points filtered = apply_filter(m.points, m.triangles, g, options, &report);
        const Points exact = spectral_filter(test_spectrum(), m.points, g);
        EXPECT_LT((filtered - exact).rowwise().norm().maxCoeff(), 1e-6 * diag);
        EXPECT_EQ(report.active_vertices, m.points.rows());
    }
}

} // namespace

TEST(Filter, FactoredSolverEqualsExactSpectralFilter) { expect_matches_spectral(Solver::Factored, 1e-10); }

TEST(Filter, PaperJacobiPcgEqualsExactSpectralFilter) { expect_matches_spectral(Solver::JacobiPcg, 1e-10); }

// Section 5 / Fig. 6: a sphere of radius r is scaled by G(2/r^2).
TEST(Filter, SphereTestRadiusScalesByGAtTwoOverRSquared) {
    const TransferFunction g = design_second_order({10, 25, 1, 30, 0});
    for (double r : {0.2, 0.3, 0.45, 0.7, 1.0, 2.0}) {
        const Mesh s = icosphere(4, r);
        const Points out = apply_filter(s.points, s.triangles, g);
        const double ratio = mean_radius(out) / r;
        EXPECT_NEAR(ratio, g(2 / (r * r)), 0.02 * std::abs(g(2 / (r * r)))) << "r = " << r;
    }
}

TEST(Filter, TranslationInvariantAndFrequenciesScaleAsOneOverLengthSquared) {
    const Mesh m = test_mesh();
    const SecondOrderSpec spec{25, 50, 0.5, 1.1, 0};
    const Points reference = apply_filter(m.points, m.triangles, design_second_order(spec));
    for (double unit : {1e-6, 1e6}) {
        // The same shape in another unit, far from the origin: the same filter is the one
        // whose frequencies are divided by unit^2.
        const Eigen::RowVector3d offset(3e3 * unit, -7e2 * unit, 1e3 * unit);
        const Points scaled = (m.points * unit).rowwise() + offset;
        const SecondOrderSpec scaled_spec{spec.s1 / (unit * unit), spec.s2 / (unit * unit), spec.G0, spec.G1, spec.Ginf};
        const Points out = apply_filter(scaled, m.triangles, design_second_order(scaled_spec));
        const Points back = (out.rowwise() - offset) / unit;
        EXPECT_LT((back - reference).rowwise().norm().maxCoeff(), 1e-8 * bbox_diagonal(m.points)) << "unit " << unit;
    }
}

TEST(Filter, NonConvergenceIsAnErrorNotAResult) {
    const Mesh m = test_mesh();
    FilterOptions options;
    options.solver = Solver::JacobiPcg;
    options.max_iterations = 3;
    try {
        apply_filter(m.points, m.triangles, design_second_order({25, 50, 1, 1.1, 0}), options);
        FAIL() << "a capped solve returned a result";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("did not converge in 3 iterations"), std::string::npos) << e.what();
    }
}

TEST(Filter, CancellationThroughProgressIsAnError) {
    const Mesh m = test_mesh();
    FilterOptions options;
    int calls = 0;
    options.progress = [&](double, const std::string&) { return ++calls < 2; };
    EXPECT_THROW(apply_filter(m.points, m.triangles, design_second_order({25, 50, 1, 1.1, 0}), options), Error);
    EXPECT_EQ(calls, 2);
}

TEST(Filter, SeveralComponentsAreFilteredIndependently) {
    // Two spheres far apart: each is its own eigenmode, scaled by G(2/r^2) about its own
    // centre (a constant per component has eigenvalue 0, and G0 = 1 keeps it).
    Mesh a = icosphere(3, 0.5), b = icosphere(3, 1.0);
    Mesh both;
    both.points.resize(a.points.rows() + b.points.rows(), 3);
    both.points << a.points, (b.points.rowwise() + Eigen::RowVector3d(10, 0, 0));
    both.triangles.resize(a.triangles.rows() + b.triangles.rows(), 3);
    both.triangles << a.triangles, (b.triangles.array() + static_cast<int>(a.points.rows())).matrix();
    const TransferFunction g = design_second_order({10, 25, 1, 30, 0});
    const Points out = apply_filter(both.points, both.triangles, g);
    const Points out_a = out.topRows(a.points.rows()), out_b = out.bottomRows(b.points.rows());
    EXPECT_NEAR(mean_radius(out_a) / 0.5, g(8.0), 0.02 * g(8.0));
    EXPECT_NEAR(mean_radius(out_b, Eigen::RowVector3d(10, 0, 0)) / 1.0, g(2.0), 0.02 * g(2.0));
}
