// Solver benchmark: the factored solver against the paper's Jacobi-PCG, the
// cheapest implicit filter (one M + hK solve), and vcglib's Taubin smoothing, on meshes
// of ~10k, ~100k and ~1M vertices normalised to unit bounding-box diagonal, for the paper's
// presets and the Butterworth lowpass; then what a preview rerun costs through a
// FilterCache. Every case runs in a forked child so that its peak memory is its own.
#include "core/design/butterworth.h"
#include "core/denoise/denoise.h"
#include "core/filter/filter.h"
#include "core/operators/laplace.h"
#include "core/operators/point_cloud_laplace.h"
#include "core/filter/region.h"
#include "core/solve/shifted_cholesky.h"
#include "core/solve/supernodal_solve.h"
#include "core/mesh/surface_measures.h"
#include "benchmark_support.h"
#include "shapes.h"
#include "core/solve/solvers.h"
#include "core/design/transfer_function.h"
#include "exact_pairs.h"

// vcglib headers are not self-contained: complex.h must come first.
#include <vcg/complex/complex.h>
#include <vcg/complex/algorithms/smooth.h>
#include <vcg/complex/algorithms/update/flag.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using namespace geofilter;
using namespace geofilter::benchmark;

namespace {

class TVertex;
class TFace;
struct TTypes : vcg::UsedTypes<vcg::Use<TVertex>::AsVertexType, vcg::Use<TFace>::AsFaceType> {};
class TVertex : public vcg::Vertex<TTypes, vcg::vertex::Coord3f, vcg::vertex::BitFlags> {};
class TFace : public vcg::Face<TTypes, vcg::face::VertexRef, vcg::face::BitFlags> {};
class TMesh : public vcg::tri::TriMesh<std::vector<TVertex>, std::vector<TFace>> {};

struct NamedMesh {
    std::string name;
    Mesh mesh;
};

Mesh read_off(const std::string& path) {
    std::ifstream in(path);
    std::string header;
    in >> header;
    if (header != "OFF") throw Error(path + ": not an OFF file");
    long nv = 0, nf = 0, ne = 0;
    in >> nv >> nf >> ne;
    Mesh m;
    m.points.resize(nv, 3);
    for (long i = 0; i < nv; ++i) in >> m.points(i, 0) >> m.points(i, 1) >> m.points(i, 2);
    std::vector<Eigen::Vector3i> tris;
    for (long f = 0; f < nf; ++f) {
        int k = 0;
        in >> k;
        std::vector<int> idx(k);
        for (int& i : idx) in >> i;
        std::string rest;
        std::getline(in, rest);
        for (int j = 1; j + 1 < k; ++j) tris.emplace_back(idx[0], idx[j], idx[j + 1]);
    }
    if (!in) throw Error(path + ": truncated OFF file");
    m.triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
    for (size_t i = 0; i < tris.size(); ++i) m.triangles.row(i) = tris[i].transpose();
    return m;
}

struct CaseResult {
    double assembly = 0, factor = 0, solve = 0, total = 0, peak_mib = 0;
    double pcg_seconds = 0;
    int pcg_iterations = 0;
    bool pcg_capped = false;
    double pcg_error = 0;  // max distance to the factored result / bbox diagonal
    double floor_seconds = 0, taubin_seconds = 0;
    int fast_iterations = 0;
    int exact_pairs = 0;
    char failure[200] = {0};
};

// Runs `work` in a child process and returns what it wrote into the result, which must be
// trivially copyable and have a `char failure[200]` (the child's exception, if any).
template <class Result>
Result in_child(const std::function<void(Result&)>& work) {
    int fds[2];
    if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        Result r;
        try {
            work(r);
        } catch (const std::exception& e) {
            std::snprintf(r.failure, sizeof r.failure, "%s", e.what());
        }
        if (write(fds[1], &r, sizeof r) != static_cast<ssize_t>(sizeof r)) _exit(2);
        _exit(0);
    }
    close(fds[1]);
    Result r;
    const ssize_t got = read(fds[0], &r, sizeof r);
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (got != static_cast<ssize_t>(sizeof r)) std::snprintf(r.failure, sizeof r.failure, "child died (status %d)", status);
    return r;
}

double floor_solve(const Mesh& m, double h) {
    const double t0 = now();
    const Laplacian l = cotan_laplacian(m.points, m.triangles);
    // (M + hK) x = M p in the factored solver's symmetric frame y = M^1/2 x:
    // (Kt + I / h) y = M^1/2 p / h, factorised and solved by the solver's own code.
    const SparseMatrix kt = mass_normalized_stiffness(l);
    const Eigen::VectorXd sqrt_mass = l.mass.cwiseSqrt();
    detail::ShiftedCholesky cholesky(kt);
    cholesky.factorize(1.0 / h);
    const Eigen::MatrixXd y = cholesky.solve(sqrt_mass.asDiagonal() * m.points / h);
    const Eigen::MatrixXd x = sqrt_mass.cwiseInverse().asDiagonal() * y;
    if (!x.allFinite()) throw Error("floor solve failed");
    return now() - t0;
}

double taubin(const Mesh& m, int steps, Points* smoothed = nullptr) {
    TMesh t;
    auto vi = vcg::tri::Allocator<TMesh>::AddVertices(t, m.points.rows());
    for (Eigen::Index i = 0; i < m.points.rows(); ++i, ++vi)
        vi->P() = vcg::Point3f(float(m.points(i, 0)), float(m.points(i, 1)), float(m.points(i, 2)));
    auto fi = vcg::tri::Allocator<TMesh>::AddFaces(t, m.triangles.rows());
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f, ++fi)
        for (int k = 0; k < 3; ++k) fi->V(k) = &t.vert[m.triangles(f, k)];
    const double t0 = now();
    vcg::tri::UpdateFlags<TMesh>::FaceBorderFromNone(t);
    vcg::tri::Smooth<TMesh>::VertexCoordTaubin(t, steps, 0.5f, -0.53f);
    const double seconds = now() - t0;
    if (smoothed) {
        smoothed->resize(m.points.rows(), 3);
        for (Eigen::Index i = 0; i < m.points.rows(); ++i)
            for (int k = 0; k < 3; ++k) (*smoothed)(i, k) = t.vert[static_cast<size_t>(i)].P()[k];
    }
    return seconds;
}

std::string fmt(double v, int precision = 2) {
    std::ostringstream os;
    os.setf(std::ios::fixed);
    os.precision(precision);
    os << v;
    return os.str();
}

// Writes `text` to out_dir/file (making out_dir) and says so; 1 when out_dir cannot be made.
int write_table(const std::string& out_dir, const std::string& file, const std::string& text) {
    const std::string mkdir = "mkdir -p '" + out_dir + "'";
    if (std::system(mkdir.c_str()) != 0) return 1;
    std::ofstream(out_dir + "/" + file) << text;
    std::cout << "\nwrote " << out_dir << "/" << file << "\n";
    return 0;
}

// A region of ~1% of the mesh's vertices (the faces inside a ball around one
// vertex), filtered at its own frequency (s1 = 2/R^2, R the ball's radius) with the default
// band (blendWidth = auto = R), against the same filter on the whole mesh. The region's time
// includes computing its weight.
int region_rows(const std::vector<std::function<NamedMesh()>>& makers, const std::string& out_dir) {
    std::ostringstream table;
    table << "| mesh | vertices | filter | D: w > 0 (selected) | solved on (D + ring) | whole mesh (s) | region (s) |"
             " region / whole | outside D unchanged |\n|---|---:|---|---:|---:|---:|---:|---:|---|\n";
    std::cout << table.str() << std::flush;
    for (const auto& make : makers) {
        NamedMesh nm = make();
        normalise(nm.mesh);
        const Mesh& m = nm.mesh;
        const Eigen::RowVector3d centre = m.points.row(m.points.rows() / 3);
        std::vector<double> d(static_cast<size_t>(m.points.rows()));
        for (Eigen::Index i = 0; i < m.points.rows(); ++i) d[i] = (m.points.row(i) - centre).norm();
        std::vector<double> sorted = d;
        const size_t k = sorted.size() / 100;
        std::nth_element(sorted.begin(), sorted.begin() + k, sorted.end());
        const double radius = sorted[k];
        std::vector<int> faces;
        for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
            if (d[m.triangles(f, 0)] < radius && d[m.triangles(f, 1)] < radius && d[m.triangles(f, 2)] < radius)
                faces.push_back(static_cast<int>(f));
        const double s1 = 2 / (radius * radius);
        struct Preset {
            const char* name;
            SecondOrderSpec spec;
        };
        for (const Preset& p : {Preset{"band exaggeration", {s1, 2.4 * s1, 1, 3, 0.9}}, Preset{"lowpass", {s1, 2 * s1, 1, 1.1, 0}}}) {
            const TransferFunction g = design_second_order(p.spec);
            double whole = 0, region_s = 0;
            RegionReport region;
            bool unchanged = true;
            std::string failure;
            try {
                double t0 = now();
                const Points all = apply_filter(m.points, m.triangles, g);
                whole = now() - t0;
                t0 = now();
                const std::vector<double> w = region_weight(m.points, m.triangles, faces, std::sqrt(2 / s1));
                const Points part = apply_filter_weighted(m.points, m.triangles, g, w, {}, nullptr, &region);
                region_s = now() - t0;
                for (Eigen::Index i = 0; i < m.points.rows(); ++i)
                    if (w[i] == 0 && !(part.row(i) == m.points.row(i))) unchanged = false;
            } catch (const std::exception& e) {
                failure = e.what();
            }
            size_t selected_vertices = 0;
            for (double x : d) selected_vertices += x < radius;
            std::ostringstream row;
            row << "| " << nm.name << " | " << m.points.rows() << " | " << p.name << " (s1 = " << fmt(s1, 0) << ") | ";
            if (!failure.empty()) row << "failed: " << failure << " ||||||\n";
            else
                row << region.domain_vertices << " (" << selected_vertices << ") | " << region.submesh_vertices << " | "
                    << fmt(whole) << " | " << fmt(region_s, 3) << " | " << fmt(region_s / whole, 3) << " | "
                    << (unchanged ? "yes, bit for bit" : "NO") << " |\n";
            table << row.str();
            std::cout << row.str() << std::flush;
        }
    }
    return write_table(out_dir, "region.md", table.str());
}

// The median of an odd number of timings (the upper middle of an even one).
double median_of(std::vector<double> t) {
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

// Timings in the order they were taken, for a table cell.
std::string listed(const std::vector<double>& t, int precision) {
    std::string out;
    for (double x : t) out += (out.empty() ? "" : ", ") + fmt(x, precision);
    return out;
}

struct Preset {
    const char* name;
    TransferFunction g;
    double s1;  // the floor solves K + M / s1
};

const std::vector<Preset>& solver_table_presets() {
    static const std::vector<Preset> presets = {{"lowpass", design_second_order({25, 50, 1, 1.1, 0}), 25},
                                                {"band exaggeration", design_second_order({25, 60, 1, 3, 0}), 25},
                                                {"notch", design_second_order({630, 1260, 1, 0.01, 1.1}), 630},
                                                {"Butterworth n = 4", design_butterworth_lowpass(25, 4), 25},
                                                {"Butterworth n = 8", design_butterworth_lowpass(25, 8), 25}};
    return presets;
}

// The filter as the adapters run it (sharp pairs solved exactly where that is predicted to
// pay).
Points fast_filter(const Mesh& m, const TransferFunction& g, FilterReport& report) {
    FilterOptions options;
    options.complex_factorization = exact_pair_factorization();
    return apply_filter(m.points, m.triangles, g, options, &report);
}

// Each preset against the floor, as the README states the ratio: three rounds, each running
// the floor and the preset once (which goes first alternates from round to round), every run
// in a process of its own; the medians, their ratio, and every run, so that the floor's own
// spread shows.
int floor_ratio_rows(const std::vector<std::function<NamedMesh()>>& makers, const std::string& out_dir) {
    constexpr int rounds = 3;
    std::ostringstream table;
    table << "| mesh | vertices | filter | floor, median (runs) (s) | filter, median (runs) (s) | filter / floor (medians) |\n"
             "|---|---:|---|---|---|---:|\n";
    std::cout << table.str() << std::flush;
    for (const auto& make : makers) {
        NamedMesh nm = make();
        normalise(nm.mesh);
        const Mesh& m = nm.mesh;
        for (const Preset& p : solver_table_presets()) {
            std::vector<double> floor_s, filter_s;
            std::string failure;
            for (int round = 0; round < rounds && failure.empty(); ++round)
                for (int k = 0; k < 2; ++k) {
                    const bool floor_now = (k == 0) == (round % 2 == 0);
                    const CaseResult r = in_child<CaseResult>([&](CaseResult& r) {
                        if (floor_now) r.floor_seconds = floor_solve(m, 1.0 / p.s1);
                        else {
                            FilterReport report;
                            fast_filter(m, p.g, report);
                            r.total = report.seconds_total;
                        }
                    });
                    if (r.failure[0]) failure = r.failure;
                    (floor_now ? floor_s : filter_s).push_back(floor_now ? r.floor_seconds : r.total);
                }
            std::ostringstream row;
            row << "| " << nm.name << " | " << m.points.rows() << " | " << p.name << " | ";
            if (!failure.empty()) row << "failed: " << failure << " |||\n";
            else
                row << fmt(median_of(floor_s)) << " (" << listed(floor_s, 2) << ") | " << fmt(median_of(filter_s)) << " ("
                    << listed(filter_s, 2) << ") | " << fmt(median_of(filter_s) / median_of(floor_s)) << " |\n";
            table << row.str();
            std::cout << row.str() << std::flush;
        }
    }
    return write_table(out_dir, "floor.md", table.str());
}

// Denoise with nothing selected on large meshes: noise of 0.3 mean edge lengths along the
// clean mesh's normals (fixed seed). Denoise as shipped (above denoise_scoring_vertices it
// scores its candidates on patches), three runs alternated with three of 10 steps of
// vcglib's Taubin (MeshLab's default), medians and spreads; where it takes minutes no
// more, the same Denoise scoring on the whole mesh; the chosen lowpass run once on its own
// (what no choice can undercut); each result's RMS distance to the clean vertices in mean
// edge lengths; and where the median run's time went.
int denoise_rows(const std::vector<std::function<NamedMesh()>>& makers, const std::string& out_dir) {
    constexpr int runs = 3;
    constexpr Eigen::Index whole_mesh_up_to = 300000;  // above, scoring the whole mesh takes minutes
    std::ostringstream table;
    table << "| mesh | vertices | Denoise, median of 3 (s) | its runs (s) | the median run: variance, direction and patches, scoring, final (s) |"
             " scored on | Denoise scored on the whole mesh (s) | the chosen lowpass alone (s) | Taubin x10, median (its runs) (s) |"
             " RMS / h: input, Denoise, whole, Taubin x10 |\n"
             "|---|---:|---:|---|---|---|---:|---:|---|---|\n";
    std::cout << table.str() << std::flush;
    for (const auto& make : makers) {
        NamedMesh nm = make();
        normalise(nm.mesh);
        const Mesh& clean = nm.mesh;
        const double h = mean_edge_length(clean.points, clean.triangles);
        const Mesh noisy{noised_along_normals(clean, 0.3 * h, 41), clean.triangles};
        const auto rms = [&](const Points& x) { return std::sqrt((x - clean.points).rowwise().squaredNorm().mean()) / h; };
        std::ostringstream row;
        row << "| " << nm.name << " | " << clean.points.rows() << " | ";
        try {
            std::vector<double> denoise_s, taubin_s;
            std::vector<SamplingDenoise> shipped;
            Points taubin_points;
            for (int run = 0; run < runs; ++run) {
                const double t0 = now();
                shipped.push_back(denoise_sampling_noise(noisy.points, noisy.triangles, denoise_order, {}, {}));
                denoise_s.push_back(now() - t0);
                taubin_s.push_back(taubin(noisy, 10, &taubin_points));
            }
            const double median = median_of(denoise_s);
            const SamplingDenoise& d =
                shipped[static_cast<std::size_t>(std::find(denoise_s.begin(), denoise_s.end(), median) - denoise_s.begin())];
            std::string whole_s = "not run (above " + std::to_string(whole_mesh_up_to / 1000) + "k vertices)", whole_rms = "-";
            if (clean.points.rows() <= whole_mesh_up_to) {
                const double t0 = now();
                const SamplingDenoise whole = denoise_sampling_noise(noisy.points, noisy.triangles, denoise_order, {}, {},
                                                                     std::numeric_limits<int>::max());
                whole_s = fmt(now() - t0, 1);
                whole_rms = fmt(rms(whole.points), 3);
            }
            FilterOptions o;
            o.op = d.design.op;
            const double t0 = now();
            apply_filter(noisy.points, noisy.triangles, d.design.g, o);
            const double lowpass_s = now() - t0;
            row << fmt(median, 1) << " | " << listed(denoise_s, 1) << " | " << fmt(d.seconds.variance, 1) << ", "
                << fmt(d.seconds.direction, 1) << ", " << fmt(d.seconds.scoring, 1) << ", " << fmt(d.seconds.final_run, 1) << " | "
                << (d.scoring_patches ? std::to_string(d.scoring_patches) + " patches, " + std::to_string(d.scored_vertices) + " vertices"
                                      : std::string("the whole mesh"))
                << " | " << whole_s << " | " << fmt(lowpass_s, 1) << " | " << fmt(median_of(taubin_s)) << " (" << listed(taubin_s, 2)
                << ") | " << fmt(rms(noisy.points), 3) << ", " << fmt(rms(d.points), 3) << ", " << whole_rms << ", "
                << fmt(rms(taubin_points), 3) << " |\n";
        } catch (const std::exception& e) {
            row << "failed: " << e.what() << " |||||||\n";
        }
        table << row.str();
        std::cout << row.str() << std::flush;
    }
    return write_table(out_dir, "denoise.md", table.str());
}

// What MeshLab's Preview costs: through one FilterCache, a first lowpass, the same lowpass
// with s1 and s2 10% higher (the feature radius 5% smaller in the dialog), then that filter
// again (Apply after the preview), then its gain at the feature raised from 1.1 to 1.5 (a
// gain change moves the poles too). In a child process, like every case.
std::string preview_row(const std::string& name, const Mesh& m) {
    struct PreviewTimes {
        double first = 0, changed = 0, again = 0, gain = 0;
        double changed_factor = 0, changed_solve = 0;  // the parameter change, broken down
        double gain_factor = 0, gain_solve = 0;  // likewise the gain change
        int changed_iterations = 0, gain_iterations = 0;
        char changed_reuse[32] = {0}, again_reuse[32] = {0}, gain_reuse[32] = {0};
        char failure[200] = {0};
    };
    const PreviewTimes times = in_child<PreviewTimes>([&](PreviewTimes& t) {
        FilterCache cache;
        FilterReport report;
        // What the plugins run: pairs solved exactly where that is predicted to pay.
        FilterOptions adapters;
        adapters.complex_factorization = exact_pair_factorization();
        apply_filter(m.points, m.triangles, design_second_order({25, 50, 1, 1.1, 0}), adapters, &report, &cache);
        t.first = report.seconds_total;
        apply_filter(m.points, m.triangles, design_second_order({27.5, 55, 1, 1.1, 0}), adapters, &report, &cache);
        t.changed = report.seconds_total;
        t.changed_factor = report.seconds_factorization;
        t.changed_solve = report.seconds_solve;
        t.changed_iterations = report.iterations;
        std::snprintf(t.changed_reuse, sizeof t.changed_reuse, "%s", report.reused.c_str());
        apply_filter(m.points, m.triangles, design_second_order({27.5, 55, 1, 1.1, 0}), adapters, &report, &cache);
        t.again = report.seconds_total;
        std::snprintf(t.again_reuse, sizeof t.again_reuse, "%s", report.reused.c_str());
        apply_filter(m.points, m.triangles, design_second_order({27.5, 55, 1, 1.5, 0}), adapters, &report, &cache);
        t.gain = report.seconds_total;
        t.gain_factor = report.seconds_factorization;
        t.gain_solve = report.seconds_solve;
        t.gain_iterations = report.iterations;
        std::snprintf(t.gain_reuse, sizeof t.gain_reuse, "%s", report.reused.c_str());
    });
    std::ostringstream row;
    row << "| " << name << " | " << m.points.rows() << " | ";
    if (times.failure[0]) row << "failed: " << times.failure << " |||||||\n";
    else
        row << fmt(times.first, 3) << " | " << fmt(times.changed, 3) << " (factor " << fmt(times.changed_factor, 3)
            << ", solve " << fmt(times.changed_solve, 3) << ", " << times.changed_iterations << " it.) | "
            << times.changed_reuse << " | " << fmt(times.again, 3) << " | " << times.again_reuse << " | "
            << fmt(times.gain, 3) << " (factor " << fmt(times.gain_factor, 3) << ", solve " << fmt(times.gain_solve, 3) << ", "
            << times.gain_iterations << " it.) | " << times.gain_reuse << " |\n";
    return row.str();
}

// Where a CG pair solve's time goes: one triangular sweep pair with the
// factor of Kt + |r| I (the lowpass's preconditioner), CHOLMOD's solve against the core's own
// sweep, next to the memory bandwidth that bounds it and the product with Kt each iteration
// also makes. Best of three each.
template <class F>
double best_of_three(F&& f) {
    double best = 1e300;
    for (int k = 0; k < 3; ++k) {
        const double t = now();
        f();
        best = std::min(best, now() - t);
    }
    return best;
}

int solve_profile_rows(const std::vector<std::function<NamedMesh()>>& makers) {
    std::printf("| mesh | vertices | factor entries (M) | factor MB | read GB/s | CHOLMOD solve, 1 column (s) | "
                "CHOLMOD solve, 3 columns (s) | own sweep, 3 columns (s) | own sweep: GB/s of factor | Kt product, 3 columns (s) |\n"
                "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    const double shift = std::abs(design_second_order({25, 50, 1, 1.1, 0}).poles.at(0));
    for (const auto& make : makers) {
        const NamedMesh named = make();
        const SparseMatrix kt = mass_normalized_stiffness(cotan_laplacian(named.mesh.points, named.mesh.triangles));
        detail::SupernodalCholesky llt;
        detail::use_amd_ordering(llt.cholmod());
        llt.setShift(shift);
        llt.compute(kt);
        if (llt.info() != Eigen::Success) throw Error("factorisation failed");
        const double entries = double(llt.cholmod().lnz), bytes = 8 * entries;
        std::vector<double> stream(std::size_t(entries), 1.0);
        double sink = 0;
        const double read = best_of_three([&] { for (double v : stream) sink += v; });
        static volatile double keep_the_reads;
        keep_the_reads = sink;
        stream = {};
        const Eigen::MatrixXd b3 = Eigen::MatrixXd::Random(kt.rows(), 3), b1 = b3.col(0);
        Eigen::MatrixXd out;
        const double cholmod1 = best_of_three([&] { out = llt.solve(b1); });
        const double cholmod3 = best_of_three([&] { out = llt.solve(b3); });
        const double own3 = best_of_three([&] { out = detail::solve_supernodal(llt.factor(), b3); });
        const double product = best_of_three([&] { out = kt * b3; });
        std::printf("| %s | %ld | %.1f | %.0f | %.2f | %.3f | %.3f | %.3f | %.2f | %.3f |\n", named.name.c_str(),
                    long(kt.rows()), entries / 1e6, bytes / 1e6, bytes / read / 1e9, cholmod1, cholmod3, own3,
                    2 * bytes / own3 / 1e9, product);
        std::fflush(stdout);
    }
    return 0;
}

} // namespace

// The lowpass on each mesh's vertices alone, as a point cloud (what the adapters run on a layer
// without faces): the cloud's Laplacian (k-d tree, tangent Delaunay fans), then the same
// filter, each case in its own process so that the peak is the cloud's own.
std::string cloud_rows(const std::vector<std::function<NamedMesh()>>& makers) {
    struct CloudResult {
        double laplacian = 0, filter = 0, total = 0, peak_mib = 0, mesh_total = 0, mesh_peak_mib = 0;
        char failure[200] = {0};
    };
    const TransferFunction lowpass = design_second_order({25, 50, 1, 1.1, 0});
    std::ostringstream table;
    table << "| points (a mesh's vertices) | points | cloud Laplacian (s) | lowpass (s) | total (s) | peak MiB |"
             " the mesh's lowpass (s) | its peak MiB | cloud / mesh time |\n"
          << "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& make : makers) {
        NamedMesh nm = make();
        normalise(nm.mesh);
        const Mesh& m = nm.mesh;
        if (m.points.rows() < 90000) continue;
        FilterOptions options;
        options.complex_factorization = exact_pair_factorization();
        const CloudResult mesh = in_child<CloudResult>([&](CloudResult& r) {
            FilterReport report;
            apply_filter(m.points, m.triangles, lowpass, options, &report);
            r.mesh_total = report.seconds_total;
            r.mesh_peak_mib = peak_rss_mib();
        });
        const CloudResult r = in_child<CloudResult>([&](CloudResult& r) {
            const double start = now();
            const PointCloudLaplacian cloud = point_cloud_laplacian(m.points);
            r.laplacian = now() - start;
            FilterReport report;
            apply_filter(m.points, cloud.local_triangles, lowpass, options, &report);
            r.filter = report.seconds_total;
            r.total = now() - start;
            r.peak_mib = peak_rss_mib();
        });
        std::ostringstream row;
        row << "| " << nm.name << " | " << m.points.rows() << " | ";
        if (r.failure[0] || mesh.failure[0])
            row << "failed: " << r.failure << mesh.failure << " |||||||\n";
        else
            row << fmt(r.laplacian) << " | " << fmt(r.filter) << " | " << fmt(r.total) << " | " << fmt(r.peak_mib, 0)
                << " | " << fmt(mesh.mesh_total) << " | " << fmt(mesh.mesh_peak_mib, 0) << " | "
                << fmt(r.total / mesh.mesh_total) << " |\n";
        table << row.str();
        std::cout << row.str() << std::flush;
    }
    return table.str();
}

int main(int argc, char** argv) {
    std::string out_dir = "benchmark-results", meshes_dir = "meshes";
    double pcg_budget = 60;
    double pcg_full_budget = 900;  // lowpass on meshes below 120k vertices: PCG to convergence
    // --region: only the region rows (a few minutes); --preview: only the preview rows (a minute);
    // --solve-profile: only where a CG iteration's time goes (two minutes); --floor: only each
    // preset against the floor at 1M vertices, in alternated rounds (about ten minutes);
    // --clouds: only the point-cloud rows, into clouds.md (about three minutes)
    bool quick = false, region_only = false, preview_only = false, solve_profile_only = false, denoise_only = false,
         floor_only = false, clouds_only = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--out" && i + 1 < argc) out_dir = argv[++i];
        else if (a == "--meshes" && i + 1 < argc) meshes_dir = argv[++i];
        else if (a == "--pcg-seconds" && i + 1 < argc) pcg_budget = std::stod(argv[++i]);
        else if (a == "--pcg-full-seconds" && i + 1 < argc) pcg_full_budget = std::stod(argv[++i]);
        else if (a == "--quick") quick = true;
        else if (a == "--region") region_only = true;
        else if (a == "--preview") preview_only = true;
        else if (a == "--solve-profile") solve_profile_only = true;
        else if (a == "--denoise") denoise_only = true;
        else if (a == "--floor") floor_only = true;
        else if (a == "--clouds") clouds_only = true;
        else {
            std::cerr << "usage: geofilter_benchmark [--out DIR] [--meshes DIR] [--pcg-seconds S] [--pcg-full-seconds S]"
                         " [--quick] [--region] [--preview] [--solve-profile] [--denoise] [--floor] [--clouds]\n";
            return 2;
        }
    }

    std::vector<std::function<NamedMesh()>> makers;
    auto perturbed_icosphere = [](int level) {
        return [level]() {
            Mesh m = icosphere(level);
            // Noise at the edge-length scale: every frequency band has content.
            perturb_radially(m, 0.3 * std::pow(0.5, level), 17);
            return NamedMesh{"perturbed icosphere L" + std::to_string(level), m};
        };
    };
    makers.push_back(perturbed_icosphere(5));  // 10,242 vertices
    if (!quick) {
        // ~100k: the size at which the issue asks for a 100x lead over the paper's PCG on the
        // lowpass, so that PCG runs to convergence there (see --pcg-full-seconds).
        makers.push_back([]() {
            Mesh m = torus(316, 316, 1.0, 0.4);
            perturb_radially(m, 0.0015, 29);
            return NamedMesh{"perturbed torus 316x316", m};
        });
        makers.push_back(perturbed_icosphere(7));  // 163,842
        makers.push_back([]() { return NamedMesh{"perturbed torus 1000x1000", perturbed_torus_1m()}; });
    }
    // A real scan, subdivided (each level splits every triangle in four): 17k, 280k, 1.1M.
    const std::string human = meshes_dir + "/man.off";
    if (!std::ifstream(human).good()) {
        std::cerr << "geofilter_benchmark: " << human << " not found: run scripts/setup.sh (or pass --meshes DIR)\n";
        return 1;
    }
    for (int levels : quick ? std::vector<int>{0} : std::vector<int>{0, 2, 3})
        makers.push_back([human, levels]() {
            Mesh m = read_off(human);
            for (int l = 0; l < levels; ++l) m = subdivide(m);
            return NamedMesh{"man" + (levels ? " subdivided x" + std::to_string(levels) : std::string()), m};
        });

    if (solve_profile_only)  // the ~1M-vertex meshes (--quick: the small ones)
        return solve_profile_rows(quick ? makers : std::vector<std::function<NamedMesh()>>{makers[3], makers.back()});
    if (denoise_only) {
        // Clean meshes: the torus at 160k and 1M vertices, the scan subdivided to 280k and 1.1M (--quick: the scan).
        std::vector<std::function<NamedMesh()>> clean{[]() { return NamedMesh{"torus 400x400", torus(400, 400, 1.0, 0.4)}; },
                                                      makers[makers.size() - 2],
                                                      []() { return NamedMesh{"torus 1000x1000", torus(1000, 1000, 1.0, 0.4)}; },
                                                      makers.back()};
        return denoise_rows(quick ? std::vector<std::function<NamedMesh()>>{makers.back()} : clean, out_dir);
    }
    if (floor_only)  // the ~1M-vertex meshes (--quick: the small ones)
        return floor_ratio_rows(quick ? makers : std::vector<std::function<NamedMesh()>>{makers[3], makers.back()}, out_dir);
    if (region_only) {
        // The ~1M-vertex meshes: the synthetic torus and the subdivided scan (--quick: the small ones).
        return region_rows(quick ? makers : std::vector<std::function<NamedMesh()>>{makers[3], makers.back()}, out_dir);
    }

    if (clouds_only) return write_table(out_dir, "clouds.md", cloud_rows(makers));

    const std::vector<Preset>& presets = solver_table_presets();
    std::ostringstream preview;
    preview << "| mesh | vertices | first lowpass (s) | s1, s2 +10% (s) | reused | same again, Apply (s) | reused | G1 1.1 -> 1.5 (s) | reused |\n"
            << "|---|---:|---:|---:|---|---:|---|---:|---|\n";

    std::ostringstream table, csv;
    table << "| mesh | vertices | filter | fast: assembly | factor | solve | total (s) | peak MiB | PCG time (s) | PCG it. | PCG / fast | floor (s) | fast / floor | Taubin x50 (s) |\n"
          << "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    csv << "# vertices filter fast_total pcg_seconds pcg_capped floor taubin\n";

    if (preview_only) {
        for (const auto& make : makers) {
            NamedMesh nm = make();
            if (nm.mesh.points.rows() > FilterCache().max_vertices()) continue;
            normalise(nm.mesh);
            preview << preview_row(nm.name, nm.mesh);
        }
        std::cout << preview.str();
        return 0;
    }
    std::cout << table.str() << std::flush;

    for (const auto& make : makers) {
        NamedMesh nm = make();
        normalise(nm.mesh);
        const Mesh& m = nm.mesh;
        const double taubin_s = in_child<CaseResult>([&](CaseResult& r) { r.taubin_seconds = taubin(m, 50); }).taubin_seconds;
        if (m.points.rows() <= FilterCache().max_vertices()) {
            const std::string row = preview_row(nm.name, m);
            preview << row;
            std::cout << row << std::flush;
        }
        for (const Preset& p : presets) {
            const TransferFunction& g = p.g;
            const bool lowpass = std::string(p.name) == "lowpass";
            const double budget = (lowpass && m.points.rows() < 120000) ? pcg_full_budget : pcg_budget;
            const CaseResult floor = in_child<CaseResult>([&](CaseResult& r) { r.floor_seconds = floor_solve(m, 1.0 / p.s1); });
            const CaseResult r = in_child<CaseResult>([&](CaseResult& r) {
                FilterReport report;
                const Points fast = fast_filter(m, g, report);
                r.assembly = report.seconds_assembly;
                r.factor = report.seconds_factorization;
                r.solve = report.seconds_solve;
                r.total = report.seconds_total;
                r.fast_iterations = report.iterations;
                r.exact_pairs = report.exact_pairs;
                r.peak_mib = peak_rss_mib();
                FilterOptions pcg;
                pcg.solver = Solver::JacobiPcg;
                const double start = now();
                pcg.progress = [&](double, const std::string&) { return now() - start < budget; };
                FilterReport pcg_report;
                try {
                    const Points slow = apply_filter(m.points, m.triangles, g, pcg, &pcg_report);
                    r.pcg_error = (slow - fast).rowwise().norm().maxCoeff();
                    r.pcg_iterations = pcg_report.iterations;
                } catch (const Error&) {
                    r.pcg_capped = true;
                }
                r.pcg_seconds = now() - start;
            });
            std::ostringstream row;
            row << "| " << nm.name << " | " << m.points.rows() << " | " << p.name << " | ";
            if (r.failure[0]) {
                row << "failed: " << r.failure << " |||||||||||\n";
            } else {
                const std::string pcg_time = r.pcg_capped ? "> " + fmt(budget, 0) : fmt(r.pcg_seconds, 1);
                const std::string ratio = (r.pcg_capped ? "> " : "") + fmt(r.pcg_seconds / r.total, 0);
                row << fmt(r.assembly) << " | " << fmt(r.factor) << " | " << fmt(r.solve) << " (" << r.fast_iterations
                    << " it." << (r.exact_pairs ? ", " + std::to_string(r.exact_pairs) + " exact" : std::string()) << ") | " << fmt(r.total) << " | " << fmt(r.peak_mib, 0) << " | " << pcg_time << " | "
                    << (r.pcg_capped ? std::string("capped") : std::to_string(r.pcg_iterations)) << " | " << ratio << " | "
                    << fmt(floor.floor_seconds) << " | " << fmt(r.total / floor.floor_seconds) << " | " << fmt(taubin_s) << " |\n";
                if (!r.pcg_capped && r.pcg_error > 1e-6)
                    row << "<!-- warning: PCG and factored results differ by " << r.pcg_error << " -->\n";
                csv << m.points.rows() << " \"" << p.name << "\" " << r.total << " " << r.pcg_seconds << " " << r.pcg_capped
                    << " " << floor.floor_seconds << " " << taubin_s << "\n";
            }
            table << row.str();
            std::cout << row.str() << std::flush;
        }
    }

    std::string mkdir = "mkdir -p '" + out_dir + "'";
    if (std::system(mkdir.c_str()) != 0) return 1;
    const std::string clouds = cloud_rows(makers);
    std::cout << "\n" << clouds;
    std::ofstream(out_dir + "/benchmark.md") << table.str();
    std::ofstream(out_dir + "/clouds.md") << clouds;
    std::ofstream(out_dir + "/benchmark.dat") << csv.str();
    std::ofstream(out_dir + "/preview.md") << preview.str();
    std::cout << "\n" << preview.str() << "\nwrote " << out_dir << "/benchmark.md, benchmark.dat and preview.md\n";
    return 0;
}
