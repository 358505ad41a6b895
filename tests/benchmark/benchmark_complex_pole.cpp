// The experiment behind the factored solver's exact pair solves (filter_geofilter/exact_pairs):
// every complex pole pair solved by a complex-symmetric LDL^T of Kt - rI (MUMPS's parallel
// CMUMPS or ZMUMPS with SYM = 2, AMD or METIS ordering) against every pair by CG on
// (Kt - r)(Kt - conj r) preconditioned with the Cholesky factor of Kt + |r| I (apply_filter
// without a complex_factorization). Since 1 / ((s - r)(s - conj r)) = Im(1 / (s - r)) / Im r,
// one complex factorisation and its solves replace the CG for each pair, refined to the
// error budget the factored solver gives a whole filter at its default tolerance (1e-7). The
// solver itself chooses per pair by predicted cost; this measures both choices on every pair.
//
//   geofilter_complex_pole_benchmark MESH FILTER METHOD
//     MESH: torus (the 1M perturbed torus of the solver benchmark) or a mesh file and a
//           number of subdivisions, "man.off:3"; normalised to unit bounding-box diagonal
//     FILTER: lowpass | exaggeration | notch | butterworth8
//     METHOD: today (apply_filter, every pair by CG) | ldlt-amd | ldlt-metis (double
//             precision) | ldlt-single (single precision, AMD, refined in double: what the
//             solver uses)
// Prints one table row (times, factor size, peak memory of this process). One case per
// process, so that the peak is the case's own: scripts/benchmark-complex-pole.sh runs them.
#include "core/design/butterworth.h"
#include "core/solve/exact_pair.h"
#include "core/filter/filter.h"
#include "core/feature/icosphere.h"
#include "core/mesh/subdivide.h"
#include "core/operators/laplace.h"
#include "core/solve/mixed_precision_factor.h"
#include "core/design/transfer_function.h"
#include "benchmark_support.h"
#include "exact_pairs/mumps_shifted_ldlt.h"
#include "mesh_io.h"

#include <mpi.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

using namespace geofilter;
using namespace geofilter::benchmark;

namespace {

Mesh load(const std::string& spec) {
    Mesh m;
    if (spec == "torus") {
        m = perturbed_torus_1m();
    } else {
        const auto colon = spec.rfind(':');
        const std::string path = spec.substr(0, colon);
        const cli::MeshFile file = cli::MeshFile::read(path);
        m.points = file.points();
        m.triangles = file.triangles();
        for (int l = colon == std::string::npos ? 0 : std::stoi(spec.substr(colon + 1)); l > 0; --l) m = subdivide(m);
    }
    normalise(m);
    return m;
}

TransferFunction filter_named(const std::string& name) {
    if (name == "lowpass") return design_second_order({25, 50, 1, 1.1, 0});
    if (name == "exaggeration") return design_second_order({25, 60, 1, 3, 0.9});
    if (name == "notch") return design_second_order({630, 1260, 1, 0.01, 1.1});
    if (name == "butterworth8") return design_butterworth_lowpass(25, 8);
    throw Error("unknown filter " + name);
}

}  // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int status = 0;
    try {
        if (argc != 4) throw Error("usage: geofilter_complex_pole_benchmark MESH FILTER METHOD");
        const std::string mesh_spec = argv[1], filter = argv[2], method = argv[3];
        const Mesh m = load(mesh_spec);
        const TransferFunction g = filter_named(filter);
        int pairs = 0;
        for (const auto& p : g.poles) pairs += p.imag() > 0;
        std::printf("| %s | %ld | %s | %d | ", mesh_spec.c_str(), long(m.points.rows()), filter.c_str(), pairs);
        if (method == "today") {
            FilterReport report;
            const double t0 = now();
            apply_filter(m.points, m.triangles, g, FilterOptions{}, &report);
            // Every pole of these filters is in a pair, so factorisation + solve is the pairs' cost.
            std::printf("today (Cholesky of Kt + |r| I, CG: %d it.) | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f |\n",
                        report.iterations, report.seconds_assembly, report.seconds_factorization, report.seconds_solve,
                        now() - t0, report.seconds_factorization + report.seconds_solve, peak_rss_mib());
        } else {
            if (method != "ldlt-amd" && method != "ldlt-metis" && method != "ldlt-single")
                throw Error("unknown method " + method);
            const int ordering = method == "ldlt-metis" ? 5 : 0;
            const MUMPS_INT world = MUMPS_INT(MPI_Comm_c2f(MPI_COMM_WORLD));
            const double t0 = now();
            const Laplacian l = cotan_laplacian(m.points, m.triangles);
            const SparseMatrix kt = mass_normalized_stiffness(l);
            const Eigen::MatrixXd q = l.mass.cwiseSqrt().asDiagonal() * m.points;
            const double t_assembly = now() - t0;
            // The factored solver's budget for a whole filter at the default tolerance, on
            // this unit-diagonal mesh (apply_filter.cpp: allowed_error).
            const double allowed_error = FilterOptions{}.tolerance * std::sqrt(l.mass.sum());
            double t_analysis = 0, t_factor = 0, t_solve = 0;
            double factor_entries = 0, factor_mb = 0;
            int refinements = 0;
            // One analysis serves every pair: the pattern is the same, only the shift changes.
            double t = now();
            std::unique_ptr<ComplexShiftedFactor> ldlt;
            if (method == "ldlt-single")
                ldlt = std::make_unique<MixedPrecisionFactor>(
                    [&] { return std::make_unique<MumpsHostLdlt<SingleComplexMumps>>(kt, world, ordering); },
                    [&] { return std::make_unique<MumpsHostLdlt<DoubleComplexMumps>>(kt, world, ordering); });
            else
                ldlt = std::make_unique<MumpsHostLdlt<DoubleComplexMumps>>(kt, world, ordering);
            t_analysis = now() - t;
            const BlockOperator kt_times = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) { out = kt * in; };
            for (const auto& r : g.poles) {
                if (r.imag() <= 0) continue;
                t = now();
                ldlt->factorize(r);
                t_factor += now() - t;
                factor_entries = std::max(factor_entries, ldlt->factor_size().entries);
                factor_mb = std::max(factor_mb, ldlt->factor_size().megabytes_total);
                t = now();
                const detail::ExactPairSolution solved = detail::solve_pair_exactly(
                    *ldlt, r, q, allowed_error, kt_times, [](const Eigen::MatrixXd& b) { return b.norm(); });
                refinements += solved.refinements;
                t_solve += now() - t;
            }
            std::printf("%s (%s; %.3g entries, %.0f MB; %d refinement(s)) | %.2f | %.2f (analysis %.2f) | %.2f | %.2f | %.2f | %.0f |\n",
                        ldlt->name().c_str(), ordering == 5 ? "METIS" : "AMD", factor_entries, factor_mb, refinements,
                        t_assembly, t_analysis + t_factor, t_analysis, t_solve, now() - t0,
                        t_factor + t_analysis + t_solve, peak_rss_mib());
        }
    } catch (const std::exception& e) {
        std::cerr << "geofilter_complex_pole_benchmark: " << e.what() << "\n";
        status = 1;
    }
    MPI_Finalize();
    return status;
}
