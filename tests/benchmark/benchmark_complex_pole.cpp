// The experiment behind the factored solver's exact pair solves (filter_geofilter/exact_pairs):
// every complex pole pair solved by a complex-symmetric LDL^T of Kt - rI (MUMPS's parallel
// ZMUMPS with SYM = 2, AMD or METIS ordering) against every pair by CG on (Kt - r)(Kt - conj r)
// preconditioned with the Cholesky factor of Kt + |r| I (apply_filter without a
// complex_factorization). Since 1 / ((s - r)(s - conj r)) = Im(1 / (s - r)) / Im r, one complex
// factorisation and one complex solve replace the CG for each pair. The solver itself chooses
// per pair by predicted cost; this measures both choices on every pair.
//
//   geofilter_complex_pole_benchmark MESH FILTER METHOD
//     MESH: torus (the 1M perturbed torus of the solver benchmark) or a mesh file and a
//           number of subdivisions, "man.off:3"; normalised to unit bounding-box diagonal
//     FILTER: lowpass | exaggeration | notch | butterworth8
//     METHOD: today (apply_filter, every pair by CG) | ldlt-amd | ldlt-metis
// Prints one table row (times, factor size, peak memory of this process). One case per
// process, so that the peak is the case's own: scripts/benchmark-complex-pole.sh runs them.
#include "core/butterworth.h"
#include "core/filter.h"
#include "core/icosphere.h"
#include "core/laplace.h"
#include "core/transfer_function.h"
#include "benchmark_support.h"
#include "mesh_io.h"

#include <mpi.h>
#include <zmumps_c.h>

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

struct Zmumps {
    ZMUMPS_STRUC_C id{};
    Zmumps(int ordering) {
        id.comm_fortran = static_cast<MUMPS_INT>(MPI_Comm_c2f(MPI_COMM_WORLD));
        id.par = 1;
        id.sym = 2;  // general symmetric (complex symmetric, not Hermitian)
        id.job = -1;
        zmumps_c(&id);
        id.icntl[0] = id.icntl[1] = id.icntl[2] = -1;  // quiet
        id.icntl[3] = 0;
        id.icntl[6] = ordering;  // ICNTL(7): 0 AMD, 5 METIS
    }
    ~Zmumps() {
        id.job = -2;
        zmumps_c(&id);
    }
    void run(int job, const char* what) {
        id.job = job;
        zmumps_c(&id);
        if (id.infog[0] < 0)
            throw Error(std::string("ZMUMPS ") + what + " failed: INFOG(1) = " + std::to_string(id.infog[0]) +
                        ", INFOG(2) = " + std::to_string(id.infog[1]));
    }
};

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
            const int ordering = method == "ldlt-metis" ? 5 : 0;
            const double t0 = now();
            const Laplacian l = cotan_laplacian(m.points, m.triangles);
            const SparseMatrix kt = mass_normalized_stiffness(l);
            const Eigen::MatrixXd q = l.mass.cwiseSqrt().asDiagonal() * m.points;
            const double t_assembly = now() - t0;
            // The upper triangle in coordinates (1-based), one pattern for every pair.
            std::vector<MUMPS_INT> rows, cols;
            std::vector<std::complex<double>> values;
            for (Eigen::Index c = 0; c < kt.outerSize(); ++c)
                for (SparseMatrix::InnerIterator it(kt, c); it; ++it)
                    if (it.row() <= c) {
                        rows.push_back(MUMPS_INT(it.row() + 1));
                        cols.push_back(MUMPS_INT(c + 1));
                        values.emplace_back(it.value(), 0.0);
                    }
            double t_analysis = 0, t_factor = 0, t_solve = 0, error_bound = 0;
            long factor_entries = 0;
            int factor_mb = 0;
            // One analysis serves every pair: the pattern is the same, only the shift changes.
            std::vector<std::complex<double>> shifted(values);
            Zmumps z(ordering);
            z.id.n = MUMPS_INT(kt.rows());
            z.id.nnz = MUMPS_INT8(rows.size());
            z.id.irn = rows.data();
            z.id.jcn = cols.data();
            z.id.a = reinterpret_cast<ZMUMPS_COMPLEX*>(shifted.data());
            double t = now();
            if (pairs > 0) z.run(1, "analysis");
            t_analysis = now() - t;
            for (const auto& r : g.poles) {
                if (r.imag() <= 0) continue;
                for (size_t k = 0; k < shifted.size(); ++k) shifted[k] = rows[k] == cols[k] ? values[k] - r : values[k];
                t = now();
                z.run(2, "factorisation");
                t_factor += now() - t;
                factor_entries = std::max<long>(factor_entries, z.id.infog[28]);  // INFOG(29)
                factor_mb = std::max(factor_mb, int(z.id.infog[21]));             // INFOG(22)
                Eigen::MatrixXcd x = q.cast<std::complex<double>>();
                z.id.nrhs = 3;
                z.id.lrhs = MUMPS_INT(kt.rows());
                z.id.rhs = reinterpret_cast<ZMUMPS_COMPLEX*>(x.data());
                t = now();
                z.run(3, "solve");
                const Eigen::MatrixXd pair = x.imag() / r.imag();
                t_solve += now() - t;
                // A bound on the pair's error, as the factored solver's CG stops on: with
                // the spectrum of Kt real, |(Kt - rI)^-1| <= 1 / Im r, so the error in x is at
                // most |residual| / Im r and the error in Im x / Im r at most that / Im r.
                // (Real and imaginary parts apart: a complex copy of Kt would add to the peak.)
                const Eigen::MatrixXcd rx = r * x;
                const double res_re = (kt * x.real() - rx.real() - q).squaredNorm();
                const double res_im = (kt * x.imag() - rx.imag()).squaredNorm();
                error_bound = std::max(error_bound, std::sqrt(res_re + res_im) / (r.imag() * r.imag()) / pair.norm());
            }
            std::printf("complex LDL^T of Kt - rI (%s; %.3g entries, %d MB; pair error <= %.1e) | %.2f | %.2f (analysis %.2f) | %.2f | %.2f | %.2f | %.0f |\n",
                        ordering == 5 ? "METIS" : "AMD", double(factor_entries), factor_mb, error_bound, t_assembly,
                        t_analysis + t_factor, t_analysis, t_solve, now() - t0, t_factor + t_analysis + t_solve,
                        peak_rss_mib());
        }
    } catch (const std::exception& e) {
        std::cerr << "geofilter_complex_pole_benchmark: " << e.what() << "\n";
        status = 1;
    }
    MPI_Finalize();
    return status;
}
