#include "core/solve/krylov_lowpass.h"

#include "core/types.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <new>
#include <optional>
#include <string>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace geofilter {

namespace {

using Complex = std::complex<double>;

// q(s) = (1 - G(s)) / s = sum_m w_m / (s - p_m): G(s) = G(inf) + sum_m rho_m / (s - p_m)
// (partial_fractions), and G(0) = 1 cancels q's 1/s term, so w_m = -rho_m / p_m.
struct HighpassQuotient {
    std::vector<Complex> poles, weights;
};

// G qualifies (krylov_lowpass_applies).
HighpassQuotient highpass_quotient(const TransferFunction& g) {
    const std::optional<PartialFractions> fractions = partial_fractions(g);
    if (!fractions) throw Error("a Krylov lowpass needs simple poles and G finite at infinity");
    HighpassQuotient out;
    out.poles = fractions->poles;
    for (std::size_t m = 0; m < out.poles.size(); ++m) out.weights.push_back(-fractions->residues[m] / out.poles[m]);
    return out;
}

// q(T) e1 for the symmetric tridiagonal T (diagonal alpha, off-diagonal beta), one
// elimination per pole: the pivots d_j = alpha_j - p - beta^2 / d_(j-1) keep an imaginary
// part of at least |Im p| (a real pole is negative and T's eigenvalues are not). Also
// sum_m |w_m| |e_k^T (T - p_m)^-1 e1| / dist(p_m, [0, inf)): times the norm of the start
// vector and the next off-diagonal entry, a bound on the error in the mass norm. The
// process solved each (A - p_m) x = r by the Galerkin condition, whose residual is that last
// entry times beta_k v_(k+1); (A - p_m)^-1 has norm at most 1 / dist(p_m, [0, inf)) there.
struct TridiagonalQuotient {
    Eigen::VectorXd coefficients;
    double error_factor = 0;
};

TridiagonalQuotient highpass_quotient_of_tridiagonal(const std::vector<double>& alpha, const std::vector<double>& beta,
                                                     const HighpassQuotient& q) {
    const std::size_t k = alpha.size();
    TridiagonalQuotient out;
    out.coefficients = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(k));
    std::vector<Complex> pivot(k), right(k);
    for (std::size_t m = 0; m < q.poles.size(); ++m) {
        const Complex p = q.poles[m];
        // Forward elimination of (T - p I) x = e1, then back substitution.
        pivot[0] = alpha[0] - p;
        right[0] = 1;
        for (std::size_t j = 1; j < k; ++j) {
            const Complex factor = beta[j - 1] / pivot[j - 1];
            pivot[j] = alpha[j] - p - factor * beta[j - 1];
            right[j] = -factor * right[j - 1];
        }
        Complex next = right[k - 1] / pivot[k - 1];
        const double distance = p.real() <= 0 ? std::abs(p) : std::abs(p.imag());
        out.error_factor += std::abs(q.weights[m]) * std::abs(next) / distance;
        out.coefficients[static_cast<Eigen::Index>(k - 1)] += (q.weights[m] * next).real();
        for (std::size_t j = k - 1; j-- > 0;) {
            next = (right[j] - beta[j] * next) / pivot[j];
            out.coefficients[static_cast<Eigen::Index>(j)] += (q.weights[m] * next).real();
        }
    }
    return out;
}

} // namespace

bool krylov_lowpass_applies(const TransferFunction& g) {
    if (g.poles.empty() || std::abs(g(0) - 1) > 1e-12 || !partial_fractions(g)) return false;
    for (const Complex& p : g.poles)
        if (p.imag() == 0 && p.real() >= 0) return false;
    return true;
}

namespace {

// The process's large arrays, in memory asked for in 2 MB pages where the system gives them on
// request (Linux's transparent huge pages in "madvise" mode; elsewhere plain memory). The
// first write to each 4 KB page of fresh memory is a page fault. On the virtual machine these
// figures come from, that cost 0.29 s per 100 MB, about as much as the process's own passes
// over it; with 2 MB pages, 512 times fewer faults.
class LargeArray {
public:
    explicit LargeArray(std::size_t bytes) {
        constexpr std::size_t page = std::size_t(2) << 20;
        const std::size_t size = (std::max<std::size_t>(bytes, 1) + page - 1) / page * page;
        data_ = std::aligned_alloc(page, size);
        if (!data_) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        madvise(data_, size, MADV_HUGEPAGE);  // a request: refused or unsupported, the pages stay small
#endif
    }
    ~LargeArray() { std::free(data_); }
    LargeArray(const LargeArray&) = delete;
    LargeArray& operator=(const LargeArray&) = delete;
    template <class T>
    T* as(std::size_t offset_bytes = 0) {
        return reinterpret_cast<T*>(static_cast<char*>(data_) + offset_bytes);
    }

private:
    void* data_ = nullptr;
};

// krylov_lowpass for `Cols` columns (Eigen::Dynamic: any number).
template <int Cols>
Eigen::MatrixXd lanczos_lowpass(const Laplacian& laplacian, const Eigen::MatrixXd& values, const HighpassQuotient& q,
                                double allowed_error, int max_steps, KrylovReport* report) {
    SparseMatrix compressed;
    if (!laplacian.stiffness.isCompressed()) (compressed = laplacian.stiffness).makeCompressed();
    const SparseMatrix& k = laplacian.stiffness.isCompressed() ? laplacian.stiffness : compressed;
    const Eigen::Index n = values.rows(), columns = Cols == Eigen::Dynamic ? values.cols() : Cols;
    // The rows in breadth-first order of K's graph (each component from its first row): a
    // row's neighbours then lie near it in memory, where a mesh's own order can scatter them
    // (a subdivided mesh appends its edge midpoints). The products with K gather a row per
    // entry, so their time is the caches' misses: 2.05 against 1.20 s for the same 20 steps on
    // the man subdivided to 1.1M vertices. Renumbering costs a pass over K.
    std::vector<int> order, position(static_cast<std::size_t>(n), -1);
    order.reserve(static_cast<std::size_t>(n));
    for (Eigen::Index root = 0; root < n; ++root) {
        if (position[static_cast<std::size_t>(root)] >= 0) continue;
        position[static_cast<std::size_t>(root)] = static_cast<int>(order.size());
        order.push_back(static_cast<int>(root));
        for (std::size_t next = order.size() - 1; next < order.size(); ++next)
            for (SparseMatrix::InnerIterator it(k, order[next]); it; ++it)
                if (position[static_cast<std::size_t>(it.row())] < 0) {
                    position[static_cast<std::size_t>(it.row())] = static_cast<int>(order.size());
                    order.push_back(static_cast<int>(it.row()));
                }
    }
    std::vector<int> first_entry(static_cast<std::size_t>(n) + 1, 0);
    const int* k_first = k.outerIndexPtr();
    for (Eigen::Index i = 0; i < n; ++i) {
        const int old = order[static_cast<std::size_t>(i)];
        first_entry[static_cast<std::size_t>(i) + 1] = first_entry[static_cast<std::size_t>(i)] + k_first[old + 1] - k_first[old];
    }
    const std::size_t entries = static_cast<std::size_t>(first_entry.back());
    const std::size_t vector_doubles = static_cast<std::size_t>(n) * static_cast<std::size_t>(columns);
    // K's entries and rows, then six vectors: start, the values reordered, the three of the
    // recurrence, the part removed.
    LargeArray storage(entries * (sizeof(double) + sizeof(int)) + 6 * vector_doubles * sizeof(double) + 64);
    double* entry = storage.as<double>();
    int* entry_row = storage.as<int>(entries * sizeof(double));
    double* vectors = storage.as<double>((entries * (sizeof(double) + sizeof(int)) + 63) / 64 * 64);
    Eigen::VectorXd mass(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        const int old = order[static_cast<std::size_t>(i)];
        for (int p = k_first[old], to = first_entry[static_cast<std::size_t>(i)]; p < k_first[old + 1]; ++p, ++to) {
            entry_row[to] = position[static_cast<std::size_t>(k.innerIndexPtr()[p])];
            entry[to] = k.valuePtr()[p];
        }
        mass[i] = laplacian.mass[old];
    }
    // Each column's share of the Frobenius budget.
    const double allowed_per_column = allowed_error / std::sqrt(static_cast<double>(std::max<Eigen::Index>(columns, 1)));

    // The columns' processes are independent but advance together, row by row over vectors
    // stored a row at a time: each step reads K once for all of them (K is symmetric, so its
    // column i is row i) and makes two more passes over the vectors, where a pass per
    // operation and column reads them a dozen times; at a million vertices the step is
    // bound by memory traffic. (Sharing the rows out among two threads was measured slower
    // at 384k vertices.)
    using RowMajor = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Cols, Eigen::RowMajor>>;
    const auto vector_at = [&](int which) { return vectors + static_cast<std::size_t>(which) * vector_doubles; };
    // out = M^-1 K x on rows of positive mass (0 elsewhere); `each_row(i, k_x)` sees row i of K x.
    const auto apply_a = [&](const auto& x, auto& out, const auto& each_row) {
        // A local row of fixed size for three columns: the sums stay in registers.
        Eigen::Matrix<double, 1, Cols> sum = Eigen::Matrix<double, 1, Cols>::Zero(1, columns);
        for (Eigen::Index i = 0; i < n; ++i) {
            sum.setZero();
            for (int p = first_entry[i]; p < first_entry[i + 1]; ++p) sum.noalias() += entry[p] * x.row(entry_row[p]);
            const double inverse_mass = mass[i] > 0 ? 1 / mass[i] : 0.0;
            out.row(i) = sum * inverse_mass;
            each_row(i, sum);
        }
    };

    RowMajor start(vector_at(0), n, columns), reordered(vector_at(1), n, columns);
    for (Eigen::Index i = 0; i < n; ++i) reordered.row(i) = values.row(order[static_cast<std::size_t>(i)]);
    std::vector<double> start_norm(static_cast<std::size_t>(columns), 0.0);
    apply_a(reordered, start, [&](Eigen::Index i, const auto& k_x) {
        // |M^-1 K x|^2 in the mass norm: (K x)_i^2 / m_i.
        if (mass[i] > 0)
            for (Eigen::Index c = 0; c < columns; ++c)
            start_norm[static_cast<std::size_t>(c)] += k_x[c] * k_x[c] / mass[i];
    });
    // A column in the kernel of A (G(A) b = b) or whose process has ended takes no more steps.
    std::vector<bool> running(static_cast<std::size_t>(columns));
    for (Eigen::Index c = 0; c < columns; ++c) {
        start_norm[c] = std::sqrt(start_norm[c]);
        running[c] = start_norm[c] > 0;
    }
    // The Lanczos recurrence; `step` advances the moving columns by one, recording alpha and
    // beta on the first pass and replaying them on the second, where `summed` also adds each
    // column's current basis vector, times its coefficient, to the part removed. A column
    // that stops moving is not read again (its vectors become zero), so the three vectors
    // rotate through the buffers.
    std::vector<std::vector<double>> alpha(static_cast<std::size_t>(columns)), beta(alpha);
    double* rotating[3] = {vector_at(2), vector_at(3), vector_at(4)};  // previous, current, next
    std::fill(vector_at(2), vector_at(5), 0.0);
    RowMajor previous(rotating[0], n, columns), current(rotating[1], n, columns), next(rotating[2], n, columns);
    const auto restart = [&] {
        for (Eigen::Index i = 0; i < n; ++i)
            for (Eigen::Index c = 0; c < columns; ++c)
                current(i, c) = start_norm[c] > 0 ? start(i, c) / start_norm[c] : start(i, c);
    };
    std::vector<double> a(static_cast<std::size_t>(columns)), b(a), b_before(a), squared(a), kept(a);
    const auto step = [&](std::size_t j, bool record, const std::vector<bool>& moving, RowMajor* summed,
                          const std::vector<double>& coefficient) {
        for (Eigen::Index c = 0; c < columns; ++c) {
            a[c] = record || !moving[c] ? 0.0 : alpha[c][j];
            b[c] = record || !moving[c] ? 0.0 : beta[c][j];
            b_before[c] = j > 0 && moving[c] ? beta[c][j - 1] : 0.0;
            squared[c] = 0;
            kept[c] = moving[c] ? 1.0 : 0.0;  // a column that stops is zero from then on, never garbage
        }
        apply_a(current, next, [&](Eigen::Index i, const auto& k_x) {
            if (record && mass[i] > 0)  // the mass inner product of M^-1 K x with x
                for (Eigen::Index c = 0; c < columns; ++c) a[c] += k_x[c] * current(i, c);
            if (summed)
                for (Eigen::Index c = 0; c < columns; ++c) (*summed)(i, c) += coefficient[c] * current(i, c);
        });
        for (Eigen::Index i = 0; i < n; ++i)
            for (Eigen::Index c = 0; c < columns; ++c) {
                double& w = next(i, c);
                w = kept[c] * (w - a[c] * current(i, c) - b_before[c] * previous(i, c));
                if (record) squared[c] += mass[i] * w * w;
                else if (b[c] > 0) w /= b[c];
            }
        for (Eigen::Index c = 0; c < columns; ++c) {
            if (!moving[c]) continue;
            if (record) {
                b[c] = std::sqrt(squared[c]);
                alpha[c].push_back(a[c]);
                beta[c].push_back(b[c]);
            }
        }
        if (record)
            for (Eigen::Index i = 0; i < n; ++i)
                for (Eigen::Index c = 0; c < columns; ++c)
                    if (b[c] > 0) next(i, c) /= b[c];
        std::rotate(rotating, rotating + 1, rotating + 3);  // previous <- current <- next <- previous
        new (&previous) RowMajor(rotating[0], n, columns);  // Eigen's way to point a Map elsewhere
        new (&current) RowMajor(rotating[1], n, columns);
        new (&next) RowMajor(rotating[2], n, columns);
    };

    restart();
    const std::vector<double> no_coefficients;
    std::vector<TridiagonalQuotient> quotient(static_cast<std::size_t>(columns));
    std::vector<double> bound(static_cast<std::size_t>(columns), 0.0);
    std::vector<int> steps(static_cast<std::size_t>(columns), 0);
    KrylovReport r;
    for (int taken = 0; std::find(running.begin(), running.end(), true) != running.end();) {
        step(static_cast<std::size_t>(taken), true, running, nullptr, no_coefficients);
        ++taken;
        for (Eigen::Index c = 0; c < columns; ++c) {
            if (!running[c]) continue;
            steps[c] = taken;
            if (taken % 4 == 0 || beta[c].back() == 0 || taken == max_steps) {
                const std::vector<double> off(beta[c].begin(), beta[c].end() - 1);
                quotient[c] = highpass_quotient_of_tridiagonal(alpha[c], off, q);
                bound[c] = start_norm[c] * beta[c].back() * quotient[c].error_factor;
                if (bound[c] <= allowed_per_column) {
                    running[c] = false;
                } else if (taken >= max_steps) {
                    r.converged = false;
                    r.iterations = taken;
                    r.error_bound = bound[c];
                    if (report) *report = r;
                    return values;
                }
            }
        }
    }
    // The same bases again, each column summed with its coefficients.
    restart();
    RowMajor removed(vector_at(5), n, columns);
    removed.setZero();
    const int most = *std::max_element(steps.begin(), steps.end());
    std::vector<bool> moving(static_cast<std::size_t>(columns));
    std::vector<double> coefficient(static_cast<std::size_t>(columns));
    for (int j = 0; j < most; ++j) {
        for (Eigen::Index c = 0; c < columns; ++c) {
            coefficient[c] = j < steps[c] ? quotient[c].coefficients[j] : 0.0;
            moving[c] = j + 1 < steps[c];
        }
        if (j + 1 < most) {
            step(static_cast<std::size_t>(j), false, moving, &removed, coefficient);
        } else {
            for (Eigen::Index i = 0; i < n; ++i)
                for (Eigen::Index c = 0; c < columns; ++c) removed(i, c) += coefficient[c] * current(i, c);
        }
    }
    Eigen::MatrixXd out = values;
    double squared_bound = 0;
    for (Eigen::Index c = 0; c < columns; ++c) {
        if (!(start_norm[c] > 0)) continue;
        for (Eigen::Index i = 0; i < n; ++i) out(order[static_cast<std::size_t>(i)], c) -= start_norm[c] * removed(i, c);
        r.iterations = std::max(r.iterations, steps[c]);
        squared_bound += bound[c] * bound[c];
    }
    r.error_bound = std::sqrt(squared_bound);
    if (report) *report = r;
    return out;
}

} // namespace

Eigen::MatrixXd krylov_lowpass(const Laplacian& laplacian, const Eigen::MatrixXd& values, const TransferFunction& g,
                               double allowed_error, int max_steps, KrylovReport* report) {
    if (!(allowed_error > 0)) throw Error("a Krylov lowpass needs a positive allowed error (got " + format_number(allowed_error) + ")");
    if (!krylov_lowpass_applies(g))
        throw Error("a Krylov lowpass needs G(0) = 1, G finite at infinity, and simple poles off s >= 0 (at least one)");
    const HighpassQuotient q = highpass_quotient(g);
    if (values.cols() == 3) return lanczos_lowpass<3>(laplacian, values, q, allowed_error, max_steps, report);
    return lanczos_lowpass<Eigen::Dynamic>(laplacian, values, q, allowed_error, max_steps, report);
}

} // namespace geofilter
