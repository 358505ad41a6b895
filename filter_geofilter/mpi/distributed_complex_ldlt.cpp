#include "distributed_complex_ldlt.h"

#include "core/solve/mixed_precision_factor.h"
#include "exact_pairs/mumps_shifted_ldlt.h"

#include <string>
#include <vector>

namespace geofilter::mpi {

namespace {

void check_petsc(PetscErrorCode code, const char* what) {
    if (code != 0) throw Error(std::string("PETSc failed while ") + what + " for the complex LDL^T");
}

template <class Arithmetic>
class DistributedComplexLdlt : public MumpsShiftedLdlt<Arithmetic> {
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
        // A failure here would be this rank's alone (memory, PETSc): every rank learns of it
        // before the collective MUMPS calls, which would otherwise wait for this one forever.
        std::string failure;
        try {
            for (PetscInt row = first; row < end; ++row) {
                PetscInt count = 0;
                const PetscInt* columns = nullptr;
                const PetscScalar* values = nullptr;
                check_petsc(MatGetRow(kt, row, &count, &columns, &values), "reading Kt");
                for (PetscInt k = 0; k < count; ++k)
                    if (columns[k] >= row) this->add_entry(row, columns[k], values[k] - (columns[k] == row ? applied_shift : 0.0));
                check_petsc(MatRestoreRow(kt, row, &count, &columns, &values), "reading Kt");
            }
        } catch (const std::exception& e) {
            failure = e.what();
        }
        int failed = failure.empty() ? 0 : 1;
        MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, comm);
        if (failed) throw Error(failure.empty() ? "another rank could not hand MUMPS its rows of Kt" : failure);
        this->initialise(MUMPS_INT(MPI_Comm_c2f(comm)));
        this->icntl(20) = 0;  // dense right-hand sides, on the host
        this->icntl(21) = 0;  // the solution back on the host
        this->analyse(n, true);
    }

    std::string name() const override { return this->described("a complex LDL^T of Kt - r I (parallel MUMPS"); }

    // This rank's share: INFO(17), MB.
    double estimated_factorization_bytes() const override { return double(this->mumps().info[16]) * 1024.0 * 1024.0; }

    // Each rank's rows go to the host, MUMPS solves there with the distributed factor, and
    // each rank gets its rows back: 16 bytes per vertex and column each way.
    Eigen::MatrixXcd solve(const Eigen::MatrixXcd& b) override {
        const int n = this->mumps().n, columns = int(b.cols());
        Eigen::MatrixXcd whole(rank_ == 0 ? n : 0, columns);
        for (int c = 0; c < columns; ++c)
            MPI_Gatherv(b.col(c).data(), int(b.rows()), MPI_C_DOUBLE_COMPLEX, rank_ == 0 ? whole.col(c).data() : nullptr,
                        rows_per_rank_.data(), first_row_.data(), MPI_C_DOUBLE_COMPLEX, 0, comm_);
        this->solve_in_place(rank_ == 0 ? whole.data() : nullptr, columns);
        Eigen::MatrixXcd x(b.rows(), columns);
        for (int c = 0; c < columns; ++c)
            MPI_Scatterv(rank_ == 0 ? whole.col(c).data() : nullptr, rows_per_rank_.data(), first_row_.data(),
                         MPI_C_DOUBLE_COMPLEX, x.col(c).data(), int(x.rows()), MPI_C_DOUBLE_COMPLEX, 0, comm_);
        return x;
    }

private:
    MPI_Comm comm_;
    int rank_ = 0;
    std::vector<int> rows_per_rank_, first_row_;
};

} // namespace

std::unique_ptr<ComplexShiftedFactor> distributed_complex_ldlt(MPI_Comm comm, Mat kt, const double& applied_shift) {
    return std::make_unique<MixedPrecisionFactor>(
        [&] { return std::make_unique<DistributedComplexLdlt<SingleComplexMumps>>(comm, kt, applied_shift); },
        [comm, kt, &applied_shift] {
            return std::make_unique<DistributedComplexLdlt<DoubleComplexMumps>>(comm, kt, applied_shift);
        });
}

} // namespace geofilter::mpi
