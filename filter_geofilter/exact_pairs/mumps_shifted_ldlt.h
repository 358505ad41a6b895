// What the sequential (mumps_complex_ldlt.cpp), the distributed
// (mpi/distributed_complex_ldlt.cpp) and the benchmark's (benchmark_complex_pole.cpp) complex
// LDL^T of Kt - r I share: one triangle of Kt with its diagonal to shift, the MUMPS calls, and
// what their status codes mean. Header-only: each is compiled against its own MUMPS
// (sequential or parallel; the same structure, other libraries), and they never meet in one
// program. Each comes in MUMPS's two complex arithmetics: single precision (CMUMPS), whose
// factor takes half the memory and which the exact pair solve refines in double precision,
// and double (ZMUMPS), for when that refinement stalls (core/solve/mixed_precision_factor.h).
#pragma once

#include "core/solve/complex_shifted_factor.h"

#include <cmumps_c.h>
#include <zmumps_c.h>

#include <algorithm>
#include <complex>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace geofilter {

struct SingleComplexMumps {
    using Instance = CMUMPS_STRUC_C;
    using Scalar = std::complex<float>;
    static void call(Instance* id) { cmumps_c(id); }
    static constexpr const char* precision = "single precision, refined in double";
};

struct DoubleComplexMumps {
    using Instance = ZMUMPS_STRUC_C;
    using Scalar = std::complex<double>;
    static void call(Instance* id) { zmumps_c(id); }
    static constexpr const char* precision = "double precision";
};

template <class Arithmetic>
class MumpsShiftedLdlt : public ComplexShiftedFactor {
public:
    using Scalar = typename Arithmetic::Scalar;

    ~MumpsShiftedLdlt() override { release(); }
    MumpsShiftedLdlt(const MumpsShiftedLdlt&) = delete;
    MumpsShiftedLdlt& operator=(const MumpsShiftedLdlt&) = delete;

    bool holds(std::complex<double> r) const override { return factored_ && r == shift_; }

    void factorize(std::complex<double> r) override {
        if (holds(r)) return;
        factored_ = false;
        for (size_t k = 0; k < diagonal_.size(); ++k) values_[diagonal_[k]] = Scalar(unshifted_diagonal_[k] - r);
        for (int attempt = 0;; ++attempt) {
            id_.job = 2;
            Arithmetic::call(&id_);
            // INFOG(1) = -8, -9: the workspace the analysis estimated was too small for the
            // pivoting it did not foresee; more room (ICNTL(14), percent) lets it through. The
            // status is global, so every process takes the same branch.
            const int info = id_.infog[0];
            if ((info == -8 || info == -9) && attempt < 3) {
                icntl(14) = 2 * std::max<int>(icntl(14), 20);
                continue;
            }
            check(info, "factorisation");
            break;
        }
        shift_ = r;
        factored_ = true;
    }

    // INFOG(29) entries; INFOG(21), INFOG(22): MB the factorisation used on the largest
    // process and on all of them.
    ComplexFactorSize factor_size() const override {
        return {double(id_.infog[28]), double(id_.infog[20]), double(id_.infog[21])};
    }

protected:
    MumpsShiftedLdlt() = default;

    // Entry (row, column) of Kt, 0-based, row <= column: MUMPS reads a symmetric matrix from
    // one triangle (and sums what it is given twice).
    void add_entry(Eigen::Index row, Eigen::Index column, double value) {
        if (column >= std::numeric_limits<MUMPS_INT>::max())
            throw Error("the complex LDL^T takes at most 2^31 - 2 vertices");
        if (row == column) {
            diagonal_.push_back(values_.size());
            unshifted_diagonal_.push_back(value);
        }
        rows_.push_back(MUMPS_INT(row + 1));
        cols_.push_back(MUMPS_INT(column + 1));
        values_.emplace_back(Scalar(value));
    }
    size_t diagonal_entries() const { return diagonal_.size(); }

    // MUMPS on `comm_fortran`, symmetric (not Hermitian: LDL^T with pivoting), its host
    // working too, silent (it would otherwise print to the host's stdout: MeshLab's, Python's).
    void initialise(MUMPS_INT comm_fortran) {
        id_.comm_fortran = comm_fortran;
        id_.par = 1;
        id_.sym = 2;
        run(-1, "initialisation");
        initialised_ = true;
        icntl(1) = icntl(2) = icntl(3) = -1;
        icntl(4) = 0;
    }

    // The analysis of the entries added, of an n x n matrix: on the host alone, or each
    // process with its own share (`distributed`, ICNTL(18) = 3).
    void analyse(Eigen::Index n, bool distributed) {
        id_.n = MUMPS_INT(n);
        if (distributed) {
            icntl(18) = 3;
            id_.nnz_loc = MUMPS_INT8(rows_.size());
            id_.irn_loc = rows_.data();
            id_.jcn_loc = cols_.data();
            id_.a_loc = reinterpret_cast<decltype(id_.a_loc)>(values_.data());
        } else {
            id_.nnz = MUMPS_INT8(rows_.size());
            id_.irn = rows_.data();
            id_.jcn = cols_.data();
            id_.a = reinterpret_cast<decltype(id_.a)>(values_.data());
        }
        try {
            run(1, "analysis");
        } catch (...) {
            release();
            throw;
        }
    }

    // Solves for the nrhs columns at `rhs` (leading dimension n) in place, on the host (the
    // other processes pass nullptr), in the factor's precision.
    void solve_in_place(std::complex<double>* rhs, int nrhs) {
        std::vector<Scalar> rounded;
        Scalar* data = nullptr;
        if constexpr (std::is_same_v<Scalar, std::complex<double>>) {
            data = rhs;
        } else if (rhs) {
            rounded.assign(rhs, rhs + size_t(id_.n) * size_t(nrhs));
            data = rounded.data();
        }
        id_.nrhs = MUMPS_INT(nrhs);
        id_.lrhs = id_.n;
        id_.rhs = reinterpret_cast<decltype(id_.rhs)>(data);
        run(3, "solve");
        id_.rhs = nullptr;
        if constexpr (!std::is_same_v<Scalar, std::complex<double>>)
            std::copy(rounded.begin(), rounded.end(), rhs);
    }

    std::string described(const char* what) const { return std::string(what) + ", " + Arithmetic::precision + ")"; }

    MUMPS_INT& icntl(int k) { return id_.icntl[k - 1]; }
    const typename Arithmetic::Instance& mumps() const { return id_; }

private:
    void run(int job, const char* what) {
        id_.job = job;
        Arithmetic::call(&id_);
        check(id_.infog[0], what);
    }

    void check(int info, const char* what) const {
        if (info >= 0) return;
        std::string reason;
        if (info == -13) reason = " (out of memory)";
        else if (info == -10) reason = " (numerically singular)";
        throw Error(std::string("the complex LDL^T (MUMPS) failed in its ") + what + reason + ": INFOG(1) = " +
                    std::to_string(info) + ", INFOG(2) = " + std::to_string(id_.infog[1]));
    }

    void release() {
        if (!initialised_) return;
        initialised_ = false;
        id_.job = -2;
        Arithmetic::call(&id_);
    }

    typename Arithmetic::Instance id_{};
    bool initialised_ = false;
    std::vector<MUMPS_INT> rows_, cols_;
    std::vector<Scalar> values_;                // MUMPS reads this process's entries from here
    std::vector<size_t> diagonal_;              // where the diagonal sits in values_
    std::vector<double> unshifted_diagonal_;    // Kt's diagonal, to shift from
    std::complex<double> shift_;
    bool factored_ = false;
};

// Every entry of Kt on the host, solved there: the core's exact pair solve (sequential MUMPS,
// `comm_fortran` its "no MPI" value) and the benchmark (parallel MUMPS on one rank).
// `ordering` is ICNTL(7): 0 AMD, 5 METIS.
template <class Arithmetic>
class MumpsHostLdlt : public MumpsShiftedLdlt<Arithmetic> {
public:
    MumpsHostLdlt(const SparseMatrix& kt, MUMPS_INT comm_fortran, int ordering) {
        for (Eigen::Index c = 0; c < kt.outerSize(); ++c)
            for (SparseMatrix::InnerIterator it(kt, c); it; ++it)
                if (it.row() <= c) this->add_entry(it.row(), c, it.value());
        if (Eigen::Index(this->diagonal_entries()) != kt.rows())
            throw Error("the complex LDL^T needs every diagonal entry of Kt stored");
        this->initialise(comm_fortran);
        this->icntl(7) = ordering;
        this->analyse(kt.rows(), false);
    }

    std::string name() const override { return this->described("a complex LDL^T of Kt - r I (MUMPS"); }

    double estimated_factorization_bytes() const override {
        return double(this->mumps().infog[16]) * 1024.0 * 1024.0;  // INFOG(17), MB
    }

    Eigen::MatrixXcd solve(const Eigen::MatrixXcd& b) override {
        Eigen::MatrixXcd x = b;
        this->solve_in_place(x.data(), int(x.cols()));
        return x;
    }
};

} // namespace geofilter
