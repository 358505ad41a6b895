#include "core/denoise/noise_variance.h"
#include "core/denoise/normal_motion.h"
#include "core/design/butterworth.h"
#include "core/filter/filter_cache.h"
#include "core/mesh/components.h"
#include "core/mesh/surface_measures.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <thread>
#include <unordered_map>
#include <vector>

namespace geofilter {

namespace {

// The expected value of the (k+1)-th smallest of m squared standard normal numbers: what a
// neighbourhood's k-th squared residual (nth_element at k) is, in units of the noise's
// variance. The middle of many tends to the median of a chi-square with one degree of
// freedom, 0.4549; the middle of a few dozen lies 5-14 % above it (the upper middle of an
// even count, and the distribution's skew), which a plain median leaves in the estimate. By
// quadrature over z = |normal number|: the order statistic's density is
// m!/(k! (m-k-1)!) F^k (1-F)^(m-k-1) 2 phi(z), F(z) = erf(z / sqrt 2).
double expected_order_square(int m, int k) {
    const double log_coefficient = std::lgamma(m + 1.0) - std::lgamma(k + 1.0) - std::lgamma(m - k + 0.0);
    const int intervals = 4000;  // Simpson's rule on [0, 9]: the tail beyond holds under 1e-18
    const double top = 9.0, step = top / intervals;
    double sum = 0;
    for (int i = 0; i <= intervals; ++i) {
        const double z = i * step;
        const double cdf = std::erf(z / std::sqrt(2.0));
        if (cdf <= 0 || cdf >= 1) continue;
        const double density = std::exp(log_coefficient + k * std::log(cdf) + (m - k - 1) * std::log1p(-cdf) -
                                        0.5 * z * z) * 2 / std::sqrt(2 * M_PI);
        sum += (i == 0 || i == intervals ? 1 : i % 2 ? 4 : 2) * z * z * density;
    }
    return sum * step / 3;
}

// Vertices whose ring of neighbours lies in one plane with them, to within `tolerance`: the
// flat faces of a clean CAD part. Noise of any size that matters leaves no ring that flat,
// so these vertices carry none, whatever the finest band's lowpass drags into them from the
// part's edges (which on a coarse part reaches every vertex's neighbourhood).
std::vector<bool> planar_rings(const Points& points, const Triangles& triangles, const VertexNeighbours& nb,
                               double tolerance) {
    const Eigen::MatrixXd normal = vertex_normals(points, triangles);
    std::vector<bool> planar(static_cast<std::size_t>(points.rows()), false);
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
        // Three points are always in a plane: a vertex of one face (two neighbours) says nothing.
        if (normal.row(i).squaredNorm() == 0 || nb.start[i + 1] - nb.start[i] < 3) continue;
        bool flat = true;
        for (int j = nb.start[i]; j < nb.start[i + 1] && flat; ++j)
            flat = std::abs((points.row(nb.index[j]) - points.row(i)).dot(normal.row(i))) <= tolerance;
        planar[static_cast<std::size_t>(i)] = flat;
    }
    return planar;
}

} // namespace

NoiseVariance estimate_noise_variance(const Points& points, const Triangles& triangles, const FilterOptions& options,
                                      FilterCache* umbrella_cache, const std::optional<Eigen::Vector3d>& along) {
    // The direction the noise is measured along at each vertex: its normal, or the one given.
    Eigen::MatrixXd direction = smoothed_vertex_normals(points, triangles);
    if (along) {
        const Eigen::RowVector3d unit = along->normalized().transpose();
        for (Eigen::Index i = 0; i < direction.rows(); ++i)
            if (direction.row(i).squaredNorm() > 0) direction.row(i) = unit;
    }
    const double h = mean_edge_length(points, triangles);
    const double size = bounding_box_diagonal(points);
    std::mt19937_64 random(20261203);
    Eigen::VectorXd sign(points.rows());
    for (Eigen::Index i = 0; i < sign.size(); ++i) sign[i] = (random() >> 63) ? 1.0 : -1.0;

    FilterOptions o = options;
    o.op = Operator::Umbrella;
    o.progress = nullptr;
    // The umbrella ignores the positions, so the lowpass is linear and the probe can be a full
    // edge length: (F(y + h b n) - F(y)) / h is F(b n) to the solver's tolerance, set well below.
    o.tolerance = std::min(options.tolerance, 1e-4 * h / size);
    const TransferFunction finest = design_butterworth_lowpass(1.0, 4);
    // Any size: the second run takes the first one's mesh and operator (at 1M vertices, 1.4 s).
    FilterCache own(std::numeric_limits<Eigen::Index>::max());
    FilterCache& cache = umbrella_cache ? *umbrella_cache : own;
    const Points f = apply_filter(points, triangles, finest, o, nullptr, &cache);
    const Points f_probe = apply_filter(points + h * (sign.asDiagonal() * direction), triangles, finest, o, nullptr, &cache);

    Eigen::VectorXd residual = Eigen::VectorXd::Zero(points.rows());
    std::vector<bool> has_normal(static_cast<std::size_t>(points.rows()), false);
    double divergence = 0, kept = 0;
    int vertices = 0;
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
        if (direction.row(i).squaredNorm() == 0) continue;
        ++vertices;
        has_normal[static_cast<std::size_t>(i)] = true;
        residual[i] = (points.row(i) - f.row(i)).dot(direction.row(i));
        const double response = (f_probe.row(i) - f.row(i)).dot(direction.row(i)) / h;
        divergence += sign[i] * response;
        kept += response * response;
    }
    if (vertices == 0) throw Error("the mesh has no face of positive area to estimate its noise on");
    NoiseVariance out;
    out.degrees_of_freedom = divergence / vertices;
    out.kept = kept / vertices;
    // n - 2 dof + kept is the expected |(I - S) b|^2 over the probe: positive for any lowpass
    // with gains in [0, 1]; guarded against a probe that came out otherwise.
    const double removed = std::max(1.0 - 2.0 * out.degrees_of_freedom + out.kept, 1e-3);
    // Per vertex, the middle of the squared residuals over its neighbourhood (the nearest
    // vertices in rings of the vertex graph), over what it is expected to be for Gaussian
    // noise of unit variance.
    const VertexNeighbours nb = vertex_neighbours(triangles, points.rows());
    const std::vector<bool> planar = planar_rings(points, triangles, nb, planar_ring_tolerance * size);
    out.per_vertex = Eigen::VectorXd::Zero(points.rows());
    // The neighbourhoods are independent: blocks of vertices go to the machine's threads, each
    // with buffers of its own, and write the middle value and the count of each.
    Eigen::VectorXd middle_square = Eigen::VectorXd::Zero(points.rows());
    std::vector<int> counted(static_cast<std::size_t>(points.rows()), 0);
    const auto measure_block = [&](Eigen::Index first, Eigen::Index last) {
        std::vector<int> mark(static_cast<std::size_t>(points.rows()), -1);
        std::vector<int> ring, next;
        std::vector<double> squared;
        for (Eigen::Index i = first; i < last; ++i) {
            if (!has_normal[static_cast<std::size_t>(i)]) continue;
            squared.clear();
            ring.assign(1, static_cast<int>(i));
            mark[static_cast<std::size_t>(i)] = static_cast<int>(i);
            while (!ring.empty() && squared.size() < static_cast<std::size_t>(noise_neighbourhood_vertices)) {
                next.clear();
                for (int v : ring) {
                    if (has_normal[static_cast<std::size_t>(v)])
                        squared.push_back(planar[static_cast<std::size_t>(v)] ? 0.0 : residual[v] * residual[v]);
                    for (int j = nb.start[v]; j < nb.start[v + 1]; ++j) {
                        const int w = nb.index[j];
                        if (mark[static_cast<std::size_t>(w)] == i) continue;
                        mark[static_cast<std::size_t>(w)] = static_cast<int>(i);
                        next.push_back(w);
                    }
                }
                ring.swap(next);
            }
            const auto middle = squared.begin() + static_cast<std::ptrdiff_t>(squared.size() / 2);
            std::nth_element(squared.begin(), middle, squared.end());
            middle_square[i] = *middle;
            counted[static_cast<std::size_t>(i)] = static_cast<int>(squared.size());
        }
    };
    const Eigen::Index threads = std::clamp<Eigen::Index>(std::thread::hardware_concurrency(), 1, 4);
    const Eigen::Index block = (points.rows() + threads - 1) / threads;
    std::vector<std::thread> helpers;
    for (Eigen::Index t = 1; t < threads && t * block < points.rows(); ++t)
        helpers.emplace_back(measure_block, t * block, std::min(points.rows(), (t + 1) * block));
    measure_block(0, std::min(points.rows(), block));
    for (std::thread& helper : helpers) helper.join();
    std::unordered_map<int, double> order_square;  // by neighbourhood size
    double sum = 0;
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
        if (!has_normal[static_cast<std::size_t>(i)]) continue;
        const int m = counted[static_cast<std::size_t>(i)];
        auto [expected, added] = order_square.try_emplace(m, 0.0);
        if (added) expected->second = expected_order_square(m, m / 2);
        out.per_vertex[i] = middle_square[i] / expected->second / removed;
        sum += out.per_vertex[i];
    }
    // A sharp feature (a corner, a toe's tip) bends its neighbours' residuals too; an impulse
    // stands out alone (noise_variance.h).
    const auto stands_out = [&](Eigen::Index i) {
        return has_normal[static_cast<std::size_t>(i)] && out.per_vertex[i] > 0 &&
               residual[i] * residual[i] > denoise_impulse_sigmas * denoise_impulse_sigmas * out.per_vertex[i] * removed;
    };
    // Per vertex: its neighbour of the largest |residual|, and the largest |residual| of the others.
    std::vector<int> loudest(static_cast<std::size_t>(points.rows()), -1);
    Eigen::VectorXd others = Eigen::VectorXd::Zero(points.rows());
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
        double largest = -1;
        for (int j = nb.start[i]; j < nb.start[i + 1]; ++j) {
            const double r = std::abs(residual[nb.index[j]]);
            if (r > largest) {
                others[i] = std::max(others[i], largest);
                largest = r;
                loudest[static_cast<std::size_t>(i)] = nb.index[j];
            } else {
                others[i] = std::max(others[i], r);
            }
        }
    }
    // Stands out, and that much farther than every neighbour but its loudest.
    const auto clear_of_others = [&](Eigen::Index k) {
        return stands_out(k) && std::abs(residual[k]) > denoise_impulse_alone * others[k];
    };
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
        const int j = loudest[static_cast<std::size_t>(i)];
        if (j < 0 || !clear_of_others(i)) continue;
        const bool alone = std::abs(residual[i]) > denoise_impulse_alone * std::abs(residual[j]);
        const bool one_of_a_pair = loudest[static_cast<std::size_t>(j)] == i && clear_of_others(j);
        if (alone || one_of_a_pair) out.impulses.push_back(static_cast<int>(i));
    }
    out.mean = sum / vertices;
    return out;
}

double subtract_own_detail(NoiseVariance& variance, const Points& points, const Triangles& triangles, int order,
                           const FilterOptions& options, FilterCache* umbrella_cache) {
    FilterOptions o = options;
    o.op = Operator::Umbrella;
    o.progress = nullptr;
    const Points lowpassed = apply_filter(points, triangles, design_butterworth_lowpass(own_detail_cutoff, order), o, nullptr, umbrella_cache);
    // Every vertex keeps its place along the surface, so the sampling stays as it was.
    const Points smoothed = keep_normal_motion(points, lowpassed, triangles, 180);
    const Eigen::VectorXd own = estimate_noise_variance(smoothed, triangles, options, umbrella_cache).per_vertex;
    const double before = variance.per_vertex.sum();
    variance.per_vertex = (variance.per_vertex - own).cwiseMax(0.0);
    if (!(before > 0)) return 0.0;
    const double kept = variance.per_vertex.sum() / before;
    const double subtracted = variance.mean * (1 - kept);
    variance.mean *= kept;
    return subtracted;
}

} // namespace geofilter
