#include "core/solve/supernodal_solve.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

namespace geofilter::detail {

namespace {

// CHOLMOD's supernodal layout: supernode s holds columns super[s] .. super[s+1]-1 as one dense
// column-major block of pi[s+1]-pi[s] rows (row indices at s[pi[s]..], values at x[px[s]..]);
// its first rows are the supernode's own columns, so the diagonal block is the top square.
struct Supernodes {
    const int* first_column;
    const int* row_start;
    const int* value_start;
    const int* rows;
    const double* values;
    int count;
};

Supernodes supernodes_of(const cholmod_factor& f) {
    if (!f.is_super || !f.is_ll || f.itype != CHOLMOD_INT || f.xtype != CHOLMOD_REAL || f.dtype != CHOLMOD_DOUBLE ||
        f.minor < f.n)
        throw std::logic_error("apply_supernodal_inverse needs a complete supernodal LL^T factor with int indices");
    return {static_cast<const int*>(f.super), static_cast<const int*>(f.pi), static_cast<const int*>(f.px),
            static_cast<const int*>(f.s),     static_cast<const double*>(f.x), static_cast<int>(f.nsuper)};
}

// One supernode's block: its first column, width columns, height rows (the first `width` of
// them its own columns), their indices, and the column-major values.
struct Block {
    int first, width, height;
    const int* rows;
    const double* values;
};

Block block_of(const Supernodes& sn, int s) {
    const int first = sn.first_column[s], height = sn.row_start[s + 1] - sn.row_start[s];
    return {first, sn.first_column[s + 1] - first, height, sn.rows + sn.row_start[s], sn.values + sn.value_start[s]};
}

// W columns of x at a time (starting at `first_rhs`), gathered contiguously per block (column c
// at buffer + c * height), so each column of L is read once for all W and the W sums are
// independent chains (a single floating-point sum is not vectorised, and waits on itself).
template <int W>
void forward(const Supernodes& sn, Eigen::MatrixXd& x, Eigen::Index first_rhs, std::vector<double>& buffer) {
    for (int s = 0; s < sn.count; ++s) {
        const auto [first, width, height, rows, block] = block_of(sn, s);
        double* b[W];
        for (int c = 0; c < W; ++c) {
            b[c] = buffer.data() + std::size_t(c) * height;
            for (int i = 0; i < width; ++i) b[c][i] = x(first + i, first_rhs + c);
            std::fill(b[c] + width, b[c] + height, 0.0);
        }
        for (int j = 0; j < width; ++j) {
            const double* l = block + std::size_t(j) * height;
            double v[W];
            for (int c = 0; c < W; ++c) v[c] = (b[c][j] /= l[j]);
            for (int i = j + 1; i < height; ++i)
                for (int c = 0; c < W; ++c) b[c][i] -= l[i] * v[c];
        }
        for (int c = 0; c < W; ++c) {
            for (int i = 0; i < width; ++i) x(first + i, first_rhs + c) = b[c][i];
            for (int i = width; i < height; ++i) x(rows[i], first_rhs + c) += b[c][i];
        }
    }
}

template <int W>
void backward(const Supernodes& sn, Eigen::MatrixXd& x, Eigen::Index first_rhs, std::vector<double>& buffer) {
    for (int s = sn.count - 1; s >= 0; --s) {
        const auto [first, width, height, rows, block] = block_of(sn, s);
        double* b[W];
        for (int c = 0; c < W; ++c) {
            b[c] = buffer.data() + std::size_t(c) * height;
            for (int i = 0; i < height; ++i) b[c][i] = x(rows[i], first_rhs + c);
        }
        for (int j = width - 1; j >= 0; --j) {
            const double* l = block + std::size_t(j) * height;
            double sum[W] = {};
            for (int i = j + 1; i < height; ++i)
                for (int c = 0; c < W; ++c) sum[c] += l[i] * b[c][i];
            for (int c = 0; c < W; ++c) b[c][j] = (b[c][j] - sum[c]) / l[j];
        }
        for (int c = 0; c < W; ++c)
            for (int i = 0; i < width; ++i) x(first + i, first_rhs + c) = b[c][i];
    }
}

template <int W>
void sweep(const Supernodes& sn, Eigen::MatrixXd& x, Eigen::Index first_rhs, std::vector<double>& buffer) {
    forward<W>(sn, x, first_rhs, buffer);
    backward<W>(sn, x, first_rhs, buffer);
}

// Sweeps running now in this process. A sweep splits its columns between two threads only
// when it is the only one: Denoise already scores two filter runs alongside each other.
std::atomic<int> sweeps_running{0};

} // namespace

void apply_supernodal_inverse(const cholmod_factor& factor, Eigen::MatrixXd& x) {
    const Supernodes sn = supernodes_of(factor);
    if (x.rows() != Eigen::Index(factor.n)) throw std::logic_error("apply_supernodal_inverse: wrong number of rows");
    int tallest = 0;
    for (int s = 0; s < sn.count; ++s) tallest = std::max(tallest, sn.row_start[s + 1] - sn.row_start[s]);
    // The columns are independent, so two threads sweep half of them each: a single thread
    // reads the factor at well under the machine's bandwidth (the sweep's gathers wait on
    // the caches). A Preview's gain change on the 100k torus, 7 CG iterations of sweeps on
    // three columns: 0.56-0.67 s on one thread, 0.42-0.51 s on two, four alternated runs.
    // Each column's arithmetic is the same either way. Below ~1e5 factor entries a sweep
    // takes about as long as starting a thread.
    const auto columns = [&](Eigen::Index first, Eigen::Index last) {
        std::vector<double> buffer(std::size_t(tallest) * 4);
        for (Eigen::Index c = first; c < last;) {
            switch (std::min<Eigen::Index>(last - c, 4)) {
            case 4: sweep<4>(sn, x, c, buffer); c += 4; break;
            case 3: sweep<3>(sn, x, c, buffer); c += 3; break;
            case 2: sweep<2>(sn, x, c, buffer); c += 2; break;
            default: sweep<1>(sn, x, c, buffer); c += 1; break;
            }
        }
    };
    const long entries = sn.value_start[sn.count];
    const bool alone = sweeps_running.fetch_add(1) == 0;
    struct Leave {
        ~Leave() { --sweeps_running; }
    } leave;
    if (alone && x.cols() >= 2 && entries >= 100000 && std::thread::hardware_concurrency() >= 2) {
        const Eigen::Index half = (x.cols() + 1) / 2;
        std::thread other(columns, half, x.cols());
        columns(0, half);
        other.join();
    } else {
        columns(0, x.cols());
    }
}

Eigen::MatrixXd solve_supernodal(const cholmod_factor& factor, const Eigen::MatrixXd& b) {
    const Eigen::Index n = b.rows();
    if (n != Eigen::Index(factor.n)) throw std::logic_error("solve_supernodal: wrong number of rows");
    const int* perm = static_cast<const int*>(factor.Perm);
    Eigen::MatrixXd x(n, b.cols());
    for (Eigen::Index k = 0; k < n; ++k) x.row(k) = b.row(perm ? perm[k] : k);
    apply_supernodal_inverse(factor, x);
    Eigen::MatrixXd out(n, b.cols());
    for (Eigen::Index k = 0; k < n; ++k) out.row(perm ? perm[k] : k) = x.row(k);
    return out;
}

} // namespace geofilter::detail
