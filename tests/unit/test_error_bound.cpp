// The solvers stop on an error bound, so `tolerance` is a promise about the result: the
// area-weighted RMS distance to the exact filter is below tolerance x the bounding-box
// diagonal. Checked on an irregular real scan with the sharpest resonances, where CG needs
// the most iterations, against the dense spectral filter.
#include "core/filter/filter.h"
#include "real_mesh.h"
#include "spectral.h"

#include <gtest/gtest.h>

using namespace geofilter;
using namespace geofilter::reference;

TEST(ErrorBound, SharpResonancesOnARealScanMeetTheTolerance) {
    const Mesh& m = man_scan_patch();
    ASSERT_GT(m.points.rows(), 1000);
    const Spectrum spectrum = spectrum_of(m);
    const double diag = bbox_diagonal(m.points);
    const std::vector<SecondOrderSpec> sharp = {
        {630, 1260, 1, 0.01, 1.1},  // notch (Fig. 9)
        {630, 1260, 1, 3, 0.9},     // band exaggeration (Fig. 9)
        {25, 60, 1, 3, 0.9},        // band exaggeration (Fig. 10)
        {200, 300, 1, 6, 0.5},      // a sharper exaggeration
        {10, 25, 1, 30, 0},         // the sphere test's G1 = 30 (Fig. 6)
    };
    for (const SecondOrderSpec& spec : sharp) {
        const TransferFunction g = design_second_order(spec);
        const Points exact = spectral_filter(spectrum, m.points, g);
        for (Solver solver : {Solver::Factored, Solver::JacobiPcg})
            for (double tolerance : {1e-5, 1e-7}) {
                SCOPED_TRACE("s1 = " + format_number(spec.s1) + ", G1 = " + format_number(spec.G1) + ", " +
                             solver_name(solver) + ", tolerance " + format_number(tolerance));
                FilterOptions options;
                options.solver = solver;
                options.tolerance = tolerance;
                const Points out = apply_filter(m.points, m.triangles, g, options);
                EXPECT_LE(area_weighted_rms(out - exact, spectrum.mass), tolerance * diag);
            }
    }
}
