#include "distributed_complex_ldlt.h"

#include "exact_pairs/mumps_status.h"

#include <zmumps_c.h>

#include <string>
#include <vector>

namespace geofilter::mpi {

namespace {

void check_petsc(PetscErrorCode code, const char* what) {
    if (code != 0) throw Error(std::string("PETSc failed while ") + what + " for the complex LDL^T");
}

class DistributedComplexLdlt : public ComplexShiftedFactor {
public:
    DistributedComplexLdlt(MPI_Comm comm, Mat kt, double applied_shift) : comm_(comm) {
        PetscInt first = 0, end = 0, n = 0;
        check_petsc(MatGetOwnershipRange(kt, &first, &end), "reading Kt");
        check_petsc(MatGetSize(kt, &n, nullptr), "reading Kt");
        MPI_Comm_rank(comm, &rank_);
        int ranks = 1;
        MPI_Comm_size(comm, &ranks);
        rows_per_rank_.resize(size_t(ranks));
        const int mine = int(end - first);
        MPI_Allgather(&mine, 1, MPI_INT, rows_per_rank_.data(), 1, MPI_INT, comm);
        first_row_.assign(size_t(ranks), 0);
        for (size_t k = 1; k < first_row_.size(); ++k) first_row_[k] = first_row_[k - 1] + rows_per_rank_[k - 1];
        // This rank's rows, one triangle (MUMPS sums what it is given), 1-based global indices.
        for (PetscInt row = first; row < end; ++row) {
            PetscInt count = 0;
            const PetscInt* columns = nullptr;
            const PetscScalar* values = nullptr;
            check_petsc(MatGetRow(kt, row, &count, &columns, &values), "reading Kt");
            for (PetscInt k = 0; k < count; ++k)
                if (columns[k] >= row) {
                    double value = values[k];
                    if (columns[k] == row) {
                        value -= applied_shift;
                        diagonal_.push_back(values_.size());
                        unshifted_diagonal_.push_back(value);
                    }
                    rows_.push_back(MUMPS_INT(row + 1));
                    cols_.push_back(MUMPS_INT(columns[k] + 1));
                    values_.emplace_back(value, 0.0);
                }
            check_petsc(MatRestoreRow(kt, row, &count, &columns, &values), "reading Kt");
        }
        id_.comm_fortran = MUMPS_INT(MPI_Comm_c2f(comm));
        id_.par = 1;  // the host works too
        id_.sym = 2;  // symmetric, not Hermitian: LDL^T with pivoting
        run(-1, "initialisation");
        initialised_ = true;
        icntl(1) = icntl(2) = icntl(3) = -1;  // silent: the log says what happened
        icntl(4) = 0;
        icntl(18) = 3;  // each rank brings its own entries
        icntl(20) = 0;  // dense right-hand sides, on the host
        icntl(21) = 0;  // solution back on the host
        id_.n = MUMPS_INT(n);
        id_.nnz_loc = MUMPS_INT8(rows_.size());
        id_.irn_loc = rows_.data();
        id_.jcn_loc = cols_.data();
        id_.a_loc = reinterpret_cast<ZMUMPS_COMPLEX*>(values_.data());
        try {
            run(1, "analysis");
        } catch (...) {
            release();
            throw;
        }
    }

    ~DistributedComplexLdlt() override { release(); }

    std::string name() const override { return "a complex LDL^T of Kt - r I (parallel MUMPS)"; }

    // This rank's share: INFO(17), MB.
    double estimated_factorization_bytes() const override { return double(id_.info[16]) * 1024.0 * 1024.0; }

    bool holds(std::complex<double> r) const override { return factored_ && r == shift_; }

    // INFOG(29) entries; INFOG(21), INFOG(22): MB the factorisation used on the largest rank
    // and on all of them.
    ComplexFactorSize factor_size() const override {
        return {double(id_.infog[28]), double(id_.infog[20]), double(id_.infog[21])};
    }

    void factorize(std::complex<double> r) override {
        if (holds(r)) return;
        factored_ = false;
        for (size_t k = 0; k < diagonal_.size(); ++k) values_[diagonal_[k]] = unshifted_diagonal_[k] - r;
        for (int attempt = 0;; ++attempt) {
            id_.job = 2;
            zmumps_c(&id_);
            const int info = id_.infog[0];  // global: every rank takes the same branch
            if (mumps_needs_more_workspace(info) && attempt < 3) {
                icntl(14) = mumps_larger_workspace(icntl(14));
                continue;
            }
            check_mumps(info, id_.infog[1], "factorisation");
            break;
        }
        shift_ = r;
        factored_ = true;
    }

    // Each rank's rows go to the host, MUMPS solves there with the distributed factor, and
    // each rank gets its rows back: 16 bytes per vertex and column each way.
    Eigen::MatrixXcd solve(const Eigen::MatrixXcd& b) override {
        const int n = id_.n, columns = int(b.cols());
        Eigen::MatrixXcd whole(rank_ == 0 ? n : 0, columns);
        for (int c = 0; c < columns; ++c)
            MPI_Gatherv(b.col(c).data(), int(b.rows()), MPI_C_DOUBLE_COMPLEX, rank_ == 0 ? whole.col(c).data() : nullptr,
                        rows_per_rank_.data(), first_row_.data(), MPI_C_DOUBLE_COMPLEX, 0, comm_);
        id_.nrhs = MUMPS_INT(columns);
        id_.lrhs = MUMPS_INT(n);
        id_.rhs = rank_ == 0 ? reinterpret_cast<ZMUMPS_COMPLEX*>(whole.data()) : nullptr;
        run(3, "solve");
        id_.rhs = nullptr;
        Eigen::MatrixXcd x(b.rows(), columns);
        for (int c = 0; c < columns; ++c)
            MPI_Scatterv(rank_ == 0 ? whole.col(c).data() : nullptr, rows_per_rank_.data(), first_row_.data(),
                         MPI_C_DOUBLE_COMPLEX, x.col(c).data(), int(x.rows()), MPI_C_DOUBLE_COMPLEX, 0, comm_);
        return x;
    }

private:
    MUMPS_INT& icntl(int k) { return id_.icntl[k - 1]; }

    void release() {
        if (!initialised_) return;
        initialised_ = false;
        id_.job = -2;
        zmumps_c(&id_);
    }

    void run(int job, const char* what) {
        id_.job = job;
        zmumps_c(&id_);
        check_mumps(id_.infog[0], id_.infog[1], what);
    }

    MPI_Comm comm_;
    int rank_ = 0;
    std::vector<int> rows_per_rank_, first_row_;
    ZMUMPS_STRUC_C id_{};
    bool initialised_ = false;
    std::vector<MUMPS_INT> rows_, cols_;
    std::vector<std::complex<double>> values_;  // MUMPS reads this rank's entries from here
    std::vector<size_t> diagonal_;
    std::vector<double> unshifted_diagonal_;
    std::complex<double> shift_;
    bool factored_ = false;
};

} // namespace

std::unique_ptr<ComplexShiftedFactor> distributed_complex_ldlt(MPI_Comm comm, Mat kt, double applied_shift) {
    return std::make_unique<DistributedComplexLdlt>(comm, kt, applied_shift);
}

} // namespace geofilter::mpi
