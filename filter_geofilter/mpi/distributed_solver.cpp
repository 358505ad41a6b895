#include "distributed_solver.h"

#include "distributed_complex_ldlt.h"
#include "distributed_pipeline.h"
#include "ranks.h"

#include "core/solve/cascade.h"
#include "core/solve/exact_pair.h"
#include "core/solve/shifted_pair_cg.h"
#include "core/solve/solvers.h"

#include <petscksp.h>
#include <petscmat.h>

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

namespace geofilter::mpi {

namespace {

enum Command : int { finish = 0, solve = 1, filter_file = 2 };

// PETSc reports through return codes here (PetscReturnErrorHandler is pushed in main): a
// failure becomes an Error, which every rank raises when the failing call was collective.
void check(PetscErrorCode code, const char* what) {
    if (code == 0) return;
    const char* text = nullptr;
    PetscErrorMessage(code, &text, nullptr);
    throw Error(std::string("PETSc failed while ") + what + (text ? std::string(": ") + text : std::string()));
}

std::vector<double> pack(const DistributedProblem& h) {
    std::vector<double> d = {double(int(h.pole_solver)), double(h.vertices), h.allowed_error, double(h.max_iterations),
                             h.g.gain, double(h.g.numerator.size())};
    for (const auto& factor : h.g.numerator) {
        d.push_back(double(factor.size()));
        d.insert(d.end(), factor.begin(), factor.end());
    }
    d.push_back(double(h.g.poles.size()));
    for (const auto& p : h.g.poles) d.insert(d.end(), {p.real(), p.imag()});
    d.push_back(h.g.second_order ? 1 : 0);
    if (const auto& c = h.g.second_order) d.insert(d.end(), {c->a0, c->a1, c->a2, c->b0, c->b1, c->b2});
    return d;
}

DistributedProblem unpack(const std::vector<double>& d) {
    size_t k = 0;
    auto next = [&]() { return d.at(k++); };
    DistributedProblem h;
    h.pole_solver = PoleSolver(int(next()));
    h.vertices = PetscInt(next());
    h.allowed_error = next();
    h.max_iterations = int(next());
    h.g.gain = next();
    h.g.numerator.resize(size_t(next()));
    for (auto& factor : h.g.numerator) {
        factor.resize(size_t(next()));
        for (double& c : factor) c = next();
    }
    h.g.poles.resize(size_t(next()));
    for (auto& p : h.g.poles) {
        const double re = next(), im = next();
        p = {re, im};
    }
    if (next() != 0) {
        SecondOrderCoefficients c{};
        for (double* v : {&c.a0, &c.a1, &c.a2, &c.b0, &c.b1, &c.b2}) *v = next();
        h.g.second_order = c;
    }
    return h;
}

DistributedProblem broadcast_header(MPI_Comm comm, const DistributedProblem* root_header) {
    std::vector<double> packed = root_header ? pack(*root_header) : std::vector<double>{};
    unsigned long size = packed.size();
    MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG, 0, comm);
    packed.resize(size);
    MPI_Bcast(packed.data(), int(size), MPI_DOUBLE, 0, comm);
    return unpack(packed);
}

// MUMPS makes the first rank of its communicator its host, which holds the largest share of
// the factorisation (measured on the 2M-vertex torus at N = 2: 1,094 MB against 822 MB), and
// rank 0 already holds the mesh. So the solve runs on a communicator that lists the ranks in
// reverse, and the distributed numbering puts the last rank's vertices first.
MPI_Comm reversed(MPI_Comm comm) {
    const Ranks ranks(comm);
    MPI_Comm engine;
    MPI_Comm_split(comm, 0, ranks.size - 1 - ranks.rank, &engine);
    return engine;
}

// Where each rank's block starts in the solve's numbering (the reversed rank order).
std::vector<int> reversed_displacements(const std::vector<int>& counts) {
    std::vector<int> displs(counts.size(), 0);
    for (size_t r = counts.size() - 1; r-- > 0;) displs[r] = displs[r + 1] + counts[r + 1];
    return displs;
}

// The rank each vertex goes to: PETSc's MatPartitioning (PT-Scotch in Debian's PETSc) of Kt's
// graph, handed to it in contiguous blocks, so that ranks share few matrix couplings. Only
// rank 0 holds the result.
std::vector<int> partition_vertices(MPI_Comm comm, const SparseMatrix* kt, PetscInt vertices) {
    const Ranks ranks(comm);
    if (ranks.size == 1) return std::vector<int>(size_t(vertices), 0);
    std::vector<int> block_rows(size_t(ranks.size)), block_entries(size_t(ranks.size), 0);
    for (int r = 0; r < ranks.size; ++r)
        block_rows[size_t(r)] = int(vertices * (r + 1) / ranks.size - vertices * r / ranks.size);
    std::vector<int> degrees, neighbours;
    if (ranks.rank == 0) {
        degrees.resize(size_t(vertices));
        for (PetscInt v = 0, r = 0, end = block_rows[0]; v < vertices; ++v) {
            while (v >= end) end += block_rows[size_t(++r)];
            int degree = 0;
            for (SparseMatrix::InnerIterator it(*kt, v); it; ++it)
                if (it.row() != v) {
                    neighbours.push_back(int(it.row()));
                    ++degree;
                }
            degrees[size_t(v)] = degree;
            block_entries[size_t(r)] += degree;
        }
    }
    MPI_Bcast(block_entries.data(), ranks.size, MPI_INT, 0, comm);
    const int rows = block_rows[size_t(ranks.rank)], entries = block_entries[size_t(ranks.rank)];
    std::vector<int> my_degrees(static_cast<size_t>(rows));
    MPI_Scatterv(degrees.data(), block_rows.data(), displacements(block_rows).data(), MPI_INT, my_degrees.data(), rows,
                 MPI_INT, 0, comm);
    // MatCreateMPIAdj takes ownership of arrays from PetscMalloc.
    PetscInt *offsets = nullptr, *columns = nullptr;
    check(PetscMalloc1(rows + 1, &offsets), "allocating the partition graph");
    check(PetscMalloc1(std::max(entries, 1), &columns), "allocating the partition graph");
    std::vector<int> my_neighbours(static_cast<size_t>(entries));
    MPI_Scatterv(neighbours.data(), block_entries.data(), displacements(block_entries).data(), MPI_INT,
                 my_neighbours.data(), entries, MPI_INT, 0, comm);
    offsets[0] = 0;
    for (int i = 0; i < rows; ++i) offsets[i + 1] = offsets[i] + my_degrees[size_t(i)];
    std::copy(my_neighbours.begin(), my_neighbours.end(), columns);
    Mat graph;
    check(MatCreateMPIAdj(comm, rows, vertices, offsets, columns, nullptr, &graph), "building the partition graph");
    MatPartitioning partitioner;
    check(MatPartitioningCreate(comm, &partitioner), "creating the partitioner");
    check(MatPartitioningSetAdjacency(partitioner, graph), "creating the partitioner");
    check(MatPartitioningSetType(partitioner, MATPARTITIONINGPTSCOTCH), "choosing PT-Scotch");
    check(MatPartitioningSetFromOptions(partitioner), "reading the partitioner's options");
    IS owner_of_row;
    check(MatPartitioningApply(partitioner, &owner_of_row), "partitioning the mesh");
    const PetscInt* owners = nullptr;
    check(ISGetIndices(owner_of_row, &owners), "reading the partition");
    std::vector<int> my_owners(owners, owners + rows);
    check(ISRestoreIndices(owner_of_row, &owners), "reading the partition");
    ISDestroy(&owner_of_row);
    MatPartitioningDestroy(&partitioner);
    MatDestroy(&graph);
    std::vector<int> owner(ranks.rank == 0 ? size_t(vertices) : 0);
    MPI_Gatherv(my_owners.data(), rows, MPI_INT, owner.data(), block_rows.data(), displacements(block_rows).data(),
                MPI_INT, 0, comm);
    return owner;
}

// This rank's rows of Kt, a matrix on `engine` (in the solve's numbering: the last rank's
// vertices first, then the one before, ...), and of q = M^1/2 p.
struct LocalRows {
    Mat kt = nullptr;
    Eigen::MatrixXd q;
};

// On rank 0, `order` lists the vertices by new index and `new_index` is its inverse.
// `coupling_entries` (rank 0): the stored entries of Kt whose row and column live on different
// ranks, what each product with Kt sends.
LocalRows distribute_rows(MPI_Comm comm, MPI_Comm engine, const SparseMatrix* kt, const Eigen::MatrixXd* q, const std::vector<int>& owner,
                          std::vector<int>& order, std::vector<int>& row_counts, long& coupling_entries) {
    coupling_entries = 0;
    const Ranks ranks(comm);
    row_counts.assign(size_t(ranks.size), 0);
    std::vector<int> entry_counts(size_t(ranks.size), 0), lengths, columns;
    std::vector<double> values, coordinates;
    if (ranks.rank == 0) {
        const int n = int(owner.size());
        for (int v = 0; v < n; ++v) ++row_counts[size_t(owner[size_t(v)])];
        std::vector<int> next = reversed_displacements(row_counts), new_index(static_cast<size_t>(n));
        order.resize(size_t(n));
        for (int v = 0; v < n; ++v) {
            new_index[size_t(v)] = next[size_t(owner[size_t(v)])]++;
            order[size_t(new_index[size_t(v)])] = v;
        }
        lengths.reserve(static_cast<size_t>(n));
        columns.reserve(size_t(kt->nonZeros()));
        values.reserve(size_t(kt->nonZeros()));
        coordinates.reserve(size_t(n) * 3);
        std::vector<std::pair<int, double>> row;
        for (int i = 0; i < n; ++i) {  // by new index, so each rank's rows are one block
            const int v = order[size_t(i)];
            row.clear();
            // Kt is symmetric: column v holds row v.
            for (SparseMatrix::InnerIterator it(*kt, v); it; ++it) {
                row.emplace_back(new_index[size_t(it.row())], it.value());
                coupling_entries += owner[size_t(it.row())] != owner[size_t(v)];
            }
            std::sort(row.begin(), row.end());
            lengths.push_back(int(row.size()));
            entry_counts[size_t(owner[size_t(v)])] += int(row.size());
            for (const auto& [c, a] : row) {
                columns.push_back(c);
                values.push_back(a);
            }
            for (int d = 0; d < 3; ++d) coordinates.push_back((*q)(v, d));
        }
    }
    MPI_Bcast(row_counts.data(), ranks.size, MPI_INT, 0, comm);
    MPI_Bcast(entry_counts.data(), ranks.size, MPI_INT, 0, comm);
    const int rows = row_counts[size_t(ranks.rank)], entries = entry_counts[size_t(ranks.rank)];
    std::vector<int> my_lengths(static_cast<size_t>(rows)), my_columns(static_cast<size_t>(entries));
    std::vector<double> my_values(static_cast<size_t>(entries)), my_coordinates(size_t(rows) * 3);
    MPI_Scatterv(lengths.data(), row_counts.data(), reversed_displacements(row_counts).data(), MPI_INT,
                 my_lengths.data(), rows, MPI_INT, 0, comm);
    MPI_Scatterv(columns.data(), entry_counts.data(), reversed_displacements(entry_counts).data(), MPI_INT,
                 my_columns.data(), entries, MPI_INT, 0, comm);
    MPI_Scatterv(values.data(), entry_counts.data(), reversed_displacements(entry_counts).data(), MPI_DOUBLE,
                 my_values.data(), entries, MPI_DOUBLE, 0, comm);
    std::vector<int> coordinate_counts(row_counts);
    for (int& c : coordinate_counts) c *= 3;
    MPI_Scatterv(coordinates.data(), coordinate_counts.data(), reversed_displacements(coordinate_counts).data(), MPI_DOUBLE,
                 my_coordinates.data(), rows * 3, MPI_DOUBLE, 0, comm);
    lengths = {};
    columns = {};
    values = {};
    coordinates = {};

    std::vector<PetscInt> offsets(size_t(rows) + 1, 0);
    for (int i = 0; i < rows; ++i) offsets[size_t(i) + 1] = offsets[size_t(i)] + my_lengths[size_t(i)];
    LocalRows local;
    check(MatCreateMPIAIJWithArrays(engine, rows, rows, PETSC_DETERMINE, PETSC_DETERMINE, offsets.data(),
                                    my_columns.data(), my_values.data(), &local.kt),
          "assembling Kt");
    check(MatSetOption(local.kt, MAT_SYMMETRIC, PETSC_TRUE), "marking Kt symmetric");
    check(MatSetOption(local.kt, MAT_SYMMETRY_ETERNAL, PETSC_TRUE), "marking Kt symmetric");
    local.q.resize(rows, 3);
    for (int i = 0; i < rows; ++i)
        for (int d = 0; d < 3; ++d) local.q(i, d) = my_coordinates[size_t(i) * 3 + size_t(d)];
    return local;
}

void sum_over_ranks(MPI_Comm comm, Eigen::ArrayXd& sums) {
    MPI_Allreduce(MPI_IN_PLACE, sums.data(), int(sums.size()), MPI_DOUBLE, MPI_SUM, comm);
}

// The pole groups of the cascade on this rank's rows: every call is collective.
class DistributedStages : public detail::PoleGroupSolver {
public:
    // Takes `kt` over (and nulls the caller's handle): it is shifted in place for each
    // factorisation rather than copied, one matrix fewer per rank while the factor is held.
    DistributedStages(MPI_Comm comm, Mat& kt, const DistributedProblem& header, FilterReport& report)
        : comm_(comm), header_(header), report_(report), shifted_(kt) {
        kt = nullptr;
        try {
            check(MatCreateVecs(shifted_, &in_, &out_), "creating vectors");
            check(MatSetOption(shifted_, MAT_SPD, PETSC_TRUE), "marking Kt + c I positive definite");
            check(MatSetOption(shifted_, MAT_SPD_ETERNAL, PETSC_TRUE), "marking Kt + c I positive definite");
            create_pole_solver();
        } catch (...) {
            release();
            throw;
        }
    }
    ~DistributedStages() override { release(); }
    DistributedStages(const DistributedStages&) = delete;
    DistributedStages& operator=(const DistributedStages&) = delete;

    Eigen::MatrixXd polynomial(const std::vector<double>& c, const Eigen::MatrixXd& y) override {
        const auto t = std::chrono::steady_clock::now();
        Eigen::MatrixXd acc = c.back() * y;
        for (int k = int(c.size()) - 2; k >= 0; --k) {
            Eigen::MatrixXd next = kt_times(acc);
            next += c[size_t(k)] * y;
            acc.swap(next);
        }
        report_.seconds_solve += seconds_since(t);
        return acc;
    }

    Eigen::MatrixXd real_pole(double r, const Eigen::MatrixXd& y, double allowed_error, double) override {
        if (r >= 0) throw Error("unstable filter: a pole lies at s = " + format_number(r) + " >= 0");
        factorize(-r);
        const auto t = std::chrono::steady_clock::now();
        Eigen::MatrixXd solved;
        if (header_.pole_solver == PoleSolver::Direct) {
            solved = apply_factor(y);
        } else {
            // Kt - r >= -r I, so |error| <= |residual| / -r.
            const double lower = -r;
            const BlockOperator shifted = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
                out = kt_times(in) - r * in;
            };
            solved = iterate(shifted, [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) { out = apply_factor(in); }, y,
                             allowed_error, true, [lower](double residual_norm, double) { return residual_norm / lower; });
        }
        const Eigen::MatrixXd residual = kt_times(solved) - r * solved - y;
        report_.relative_residual =
            std::max(report_.relative_residual, global_norm(residual) / std::max(global_norm(y), 1e-300));
        report_.seconds_solve += seconds_since(t);
        return solved;
    }

    // As the core's: with the factor of Kt + |r| I, from its Krylov space
    // (shifted_pair_cg.h); or exactly, by parallel MUMPS's complex LDL^T of Kt - r I, where the
    // core's rule (exact_pair.h, at its default cost ratios: every rank must decide alike) says
    // it pays. The multigrid preconditioner is not (Kt + |r|)^-1 exactly, which that Krylov
    // space needs: there, CG on (Kt - r)(Kt - conj r) preconditioned with P = V-cycle^2,
    // stopped on the true residual's |r| / m, m = pair_operator_lower_bound(r).
    Eigen::MatrixXd conjugate_pair(std::complex<double> r, const Eigen::MatrixXd& y, double allowed_error,
                                   double) override {
        const double twice_re = 2 * r.real(), modulus2 = std::norm(r), shift = std::abs(r);
        if (header_.pole_solver == PoleSolver::Direct) {
            if (exact_.failed()) report_.exact_pair_note = exact_.note;
            else if (exact_.holds(r) ||
                     detail::exact_pair_pays(header_.g, r, shift, shift_ == shift, detail::PairSolveCosts{}))
                if (std::optional<Eigen::MatrixXd> x = exact_pair(r, y, allowed_error)) return *x;
            return by_shifted_cg(shift, {detail::pair_term(r)}, y, allowed_error);
        }
        factorize(shift);
        const auto t = std::chrono::steady_clock::now();
        const BlockOperator quadratic = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
            const Eigen::MatrixXd k_in = kt_times(in);
            out = kt_times(k_in);
            out -= twice_re * k_in;
            out += modulus2 * in;
        };
        const BlockOperator preconditioner = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
            out = apply_factor(apply_factor(in));
        };
        const double m = detail::pair_operator_lower_bound(r);
        const Eigen::MatrixXd x =
            iterate(quadratic, preconditioner, y, allowed_error, true, [&](double residual_norm, double) { return residual_norm / m; });
        report_.seconds_solve += seconds_since(t);
        return x;
    }

    // The core's: a Butterworth's poles together, with the one factor (direct solver only).
    std::optional<Eigen::MatrixXd> poles_at_one_shift(const PartialFractions& g, double shift, const Eigen::MatrixXd& y,
                                                      double allowed_error) override {
        if (header_.pole_solver != PoleSolver::Direct) return std::nullopt;
        Eigen::MatrixXd x = by_shifted_cg(shift, detail::shifted_terms(g), y, allowed_error);
        report_.poles_at_one_shift += static_cast<int>(g.poles.size());
        return x;
    }

private:
    Eigen::MatrixXd by_shifted_cg(double shift, const std::vector<detail::ShiftedTerm>& terms, const Eigen::MatrixXd& y,
                                  double allowed_error) {
        factorize(shift);
        const auto t = std::chrono::steady_clock::now();
        Eigen::MatrixXd x = Eigen::MatrixXd::Zero(y.rows(), y.cols());
        const PcgOutcome outcome = detail::sum_shifted_solves(
            [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) { out = apply_factor(in); }, shift, terms, y, x,
            allowed_error, header_.max_iterations, {}, [this](Eigen::ArrayXd& sums) { sum_over_ranks(comm_, sums); });
        detail::record_pcg_outcome(outcome, allowed_error, "raise maxIterations or the tolerance", report_);
        report_.seconds_solve += seconds_since(t);
        return x;
    }

    // Empty (and a note for the log) when MUMPS fails or a rank lacks the memory: CG then
    // solves this pair and every later one. All of it collective, so every rank agrees.
    std::optional<Eigen::MatrixXd> exact_pair(std::complex<double> r, const Eigen::MatrixXd& y, double allowed_error) {
        const detail::ExactPairSteps steps{
            [&] { return distributed_complex_ldlt(comm_, shifted_, applied_shift_); },
            [&](double needed_here) { return memory_shortfall(needed_here); },
            [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) { out = kt_times(in); },
            [&](const Eigen::MatrixXd& local) { return global_norm(local); },
            {}};
        std::optional<Eigen::MatrixXd> x = detail::solve_pair_exactly_or_explain(exact_, steps, r, y, allowed_error, report_);
        if (x) complex_size = exact_.factor->factor_size();
        return x;
    }

    // "" when every rank's share of the factorisation (MUMPS's estimate) fits in its share of
    // its node's available memory, else why not. Collective.
    std::string memory_shortfall(double needed_here) const {
        MPI_Comm node;
        MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
        int ranks_on_node = 1;
        MPI_Comm_size(node, &ranks_on_node);
        MPI_Comm_free(&node);
        const double available = detail::available_memory_bytes();
        const double share = available > 0 ? available / ranks_on_node : 0;
        double worst[2] = {share > 0 ? needed_here / share : 0, 0};
        worst[1] = needed_here;
        MPI_Allreduce(MPI_IN_PLACE, worst, 2, MPI_DOUBLE, MPI_MAX, comm_);
        if (worst[0] <= 1) return "";
        return "a rank would need " + format_number(worst[1] / (1 << 20), 3) + " MiB, " +
               format_number(100 * worst[0], 3) + " % of its share of the available memory";
    }

    void release() {
        exact_.factor.reset();
        KSPDestroy(&ksp_);
        MatDestroy(&shifted_);
        VecDestroy(&in_);
        VecDestroy(&out_);
    }

    void create_pole_solver() {
        check(KSPCreate(comm_, &ksp_), "creating the pole solver");
        check(KSPSetOperators(ksp_, shifted_, shifted_), "creating the pole solver");
        PC pc;
        check(KSPGetPC(ksp_, &pc), "creating the pole solver");
        if (header_.pole_solver == PoleSolver::Direct) {
            check(KSPSetType(ksp_, KSPPREONLY), "choosing the direct solver");
            check(PCSetType(pc, PCCHOLESKY), "choosing Cholesky");
            check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "choosing MUMPS");
        } else {
            // One V-cycle per application: a fixed symmetric operator, so that CG may use it.
            check(KSPSetType(ksp_, KSPPREONLY), "choosing the multigrid preconditioner");
            check(PCSetType(pc, PCHYPRE), "choosing hypre");
            check(PCHYPRESetType(pc, "boomeramg"), "choosing BoomerAMG");
        }
        check(KSPSetFromOptions(ksp_), "reading the solver's options");
    }

    // The error bound from the residual's norm (over all ranks: an extra reduction, so only
    // when `uses_residual_norm`) and the sum over columns of r'P^-1 r.
    using Bound = std::function<double(double residual_norm, double rz_sum)>;

    Eigen::MatrixXd iterate(const BlockOperator& matrix, const BlockOperator& preconditioner,
                            const Eigen::MatrixXd& y, double allowed_error, bool uses_residual_norm, const Bound& bound) {
        const ErrorBound error_bound = [&](const Eigen::MatrixXd& residual, const Eigen::ArrayXd& rz) {
            return bound(uses_residual_norm ? global_norm(residual) : 0.0, rz.sum());
        };
        Eigen::MatrixXd x = Eigen::MatrixXd::Zero(y.rows(), y.cols());
        const PcgOutcome outcome = block_pcg(matrix, preconditioner, y, x, error_bound, allowed_error,
                                             header_.max_iterations, {},
                                             [this](Eigen::ArrayXd& sums) { sum_over_ranks(comm_, sums); });
        detail::record_pcg_outcome(outcome, allowed_error, "raise maxIterations or the tolerance", report_);
        return x;
    }

    double global_norm(const Eigen::MatrixXd& local) const {
        Eigen::ArrayXd squares(1);
        squares[0] = local.squaredNorm();
        sum_over_ranks(comm_, squares);
        return std::sqrt(squares[0]);
    }

    Eigen::MatrixXd kt_times(const Eigen::MatrixXd& in) {
        Eigen::MatrixXd out(in.rows(), in.cols());
        for (Eigen::Index c = 0; c < in.cols(); ++c) {
            check(VecPlaceArray(in_, in.col(c).data()), "multiplying by Kt");
            check(VecPlaceArray(out_, out.col(c).data()), "multiplying by Kt");
            check(MatMult(shifted_, in_, out_), "multiplying by Kt");
            VecResetArray(in_);
            VecResetArray(out_);
        }
        if (applied_shift_ != 0) out -= applied_shift_ * in;
        return out;
    }

    // (Kt + c I)^-1 in: MUMPS solves the three columns at once (one forward and backward
    // sweep over the distributed factor); one V-cycle per column for the multigrid option.
    Eigen::MatrixXd apply_factor(const Eigen::MatrixXd& in) {
        Eigen::MatrixXd out(in.rows(), in.cols());
        if (header_.pole_solver == PoleSolver::Direct) {
            PC pc;
            Mat factor, b, x;
            check(KSPGetPC(ksp_, &pc), "solving with the factor");
            check(PCFactorGetMatrix(pc, &factor), "solving with the factor");
            // Eigen's column-major block is PETSc's dense local storage: no copies.
            check(MatCreateDense(comm_, in.rows(), PETSC_DECIDE, header_.vertices, in.cols(),
                                 const_cast<double*>(in.data()), &b),
                  "solving with the factor");
            check(MatCreateDense(comm_, out.rows(), PETSC_DECIDE, header_.vertices, out.cols(), out.data(), &x),
                  "solving with the factor");
            const PetscErrorCode code = MatMatSolve(factor, b, x);
            MatDestroy(&b);
            MatDestroy(&x);
            check(code, "solving with the factor");
            return out;
        }
        for (Eigen::Index c = 0; c < in.cols(); ++c) {
            check(VecPlaceArray(in_, in.col(c).data()), "applying the multigrid cycle");
            check(VecPlaceArray(out_, out.col(c).data()), "applying the multigrid cycle");
            const PetscErrorCode code = KSPSolve(ksp_, in_, out_);
            VecResetArray(in_);
            VecResetArray(out_);
            check(code, "applying the multigrid cycle");
        }
        return out;
    }

    void factorize(double shift) {
        if (shift == shift_) return;
        const auto t = std::chrono::steady_clock::now();
        shift_ = NAN;
        // MUMPS sizes its workspace from the analysis's estimate plus ICNTL(14) percent; on
        // several ranks the estimate can fall short (INFOG(1) = -9, measured at 3 ranks on the
        // bunny about one run in five). PETSc will not refactorise after that failure, so
        // the pole solver is built again, with a larger margin, and the factorisation retried.
        for (int attempt = 0;; ++attempt) {
            PC pc;
            check(KSPGetPC(ksp_, &pc), "factorising");
            if (shift != applied_shift_) {
                check(MatShift(shifted_, shift - applied_shift_), "shifting Kt");
                applied_shift_ = shift;
            }
            // The same pattern at every shift: PETSc keeps MUMPS's analysis and refactorises.
            check(KSPSetOperators(ksp_, shifted_, shifted_), "factorising");
            check(KSPSetUp(ksp_), "factorising");
            PCFailedReason failed = PC_NOERROR;
            check(PCGetFailedReason(pc, &failed), "factorising");
            if (failed == PC_NOERROR) break;
            // MUMPS's status is global: every rank sees the same failure and takes the same branch.
            if (header_.pole_solver == PoleSolver::Direct) {
                Mat factor;
                PetscInt status = 0, margin = 0;
                check(PCFactorGetMatrix(pc, &factor), "factorising");
                check(MatMumpsGetInfog(factor, 1, &status), "factorising");
                if ((status == -9 || status == -8) && attempt < 3) {
                    check(MatMumpsGetIcntl(factor, 14, &margin), "factorising");
                    const std::string larger = std::to_string(std::max<PetscInt>(2 * margin, 50));
                    workspace_retries += 1;
                    KSPDestroy(&ksp_);
                    check(PetscOptionsSetValue(nullptr, "-mat_mumps_icntl_14", larger.c_str()), "factorising");
                    create_pole_solver();
                    continue;
                }
                if (status != -10)  // -10: numerically singular, the message below
                    throw Error("MUMPS failed to factorise Kt + " + format_number(shift) + " I (its INFOG(1) = " +
                                std::to_string(status) + ")");
            }
            throw Error("the sparse Cholesky factorisation failed (Kt + " + format_number(shift) +
                        " I is not positive definite): the mesh has inverted or degenerate faces");
        }
        PC pc;
        check(KSPGetPC(ksp_, &pc), "factorising");
        shift_ = shift;
        report_.seconds_factorization += seconds_since(t);
        if (header_.pole_solver == PoleSolver::Direct) {
            Mat factor;
            check(PCFactorGetMatrix(pc, &factor), "reading the factor's size");
            // INFOG(29): entries in the factor; INFOG(21)/(22): MB the factorisation used on the
            // largest rank and on all of them (MUMPS's own counts).
            PetscInt entries = 0, largest_mb = 0, total_mb = 0;
            check(MatMumpsGetInfog(factor, 29, &entries), "reading the factor's size");
            check(MatMumpsGetInfog(factor, 21, &largest_mb), "reading the factor's size");
            check(MatMumpsGetInfog(factor, 22, &total_mb), "reading the factor's size");
            factor_entries = double(entries);
            factor_largest_mb = double(largest_mb);
            factor_total_mb = double(total_mb);
        }
    }

public:
    double factor_entries = 0, factor_largest_mb = 0, factor_total_mb = 0;
    int workspace_retries = 0;  // factorisations redone with a larger ICNTL(14)
    ComplexFactorSize complex_size;  // the last complex LDL^T's, if a pair was solved exactly

private:

    MPI_Comm comm_;
    const DistributedProblem& header_;
    FilterReport& report_;
    Mat shifted_;               // Kt + applied_shift_ I
    double applied_shift_ = 0;
    KSP ksp_ = nullptr;
    Vec in_ = nullptr, out_ = nullptr;
    double shift_ = NAN;
    detail::ExactPairState exact_;  // the complex LDL^T, and why pairs went back to CG if it failed
};

} // namespace

void check_petsc(PetscErrorCode code, const char* what) { check(code, what); }

Eigen::MatrixXd filter_rows(MPI_Comm comm, Mat& kt, const Eigen::MatrixXd& q, const DistributedProblem& problem,
                            FilterReport& report, std::string* factor_note) {
    int ranks = 1;
    MPI_Comm_size(comm, &ranks);
    Eigen::MatrixXd solved_local;
    try {
        PetscReal spectrum_max = 0;
        check(MatNorm(kt, NORM_INFINITY, &spectrum_max), "bounding Kt's spectrum");  // Gershgorin, as the core
        DistributedStages stages(comm, kt, problem, report);
        solved_local = detail::apply_factored_transfer(problem.g, q, problem.allowed_error, spectrum_max, stages);
        report.external_solver = (problem.pole_solver == PoleSolver::Multigrid
                                      ? "CG with hypre BoomerAMG (multigrid, no factor)"
                                      : "factored (MUMPS sparse Cholesky)") +
                                 std::string(" over ") + std::to_string(ranks) + " MPI rank(s)";
        if (factor_note) {
            std::string& line = *factor_note;
            if (stages.factor_entries > 0)
                line += "; MUMPS factor " + format_number(stages.factor_entries, 4) + " entries (" +
                        format_number(stages.factor_entries / double(problem.vertices), 4) + " per vertex), factorisation memory " +
                        format_number(stages.factor_largest_mb, 4) + " MB on the largest rank, " +
                        format_number(stages.factor_total_mb, 4) + " MB in all";
            if (stages.complex_size.entries > 0)
                line += "; MUMPS complex LDL^T " + format_number(stages.complex_size.entries, 4) + " entries (" +
                        format_number(stages.complex_size.entries / double(problem.vertices), 4) +
                        " per vertex), factorisation memory " +
                        format_number(stages.complex_size.megabytes_largest_process, 4) + " MB on the largest rank, " +
                        format_number(stages.complex_size.megabytes_total, 4) + " MB in all";
            if (stages.workspace_retries > 0)
                line += " (after " + std::to_string(stages.workspace_retries) +
                        " retry with a larger workspace: MUMPS's estimate fell short, INFOG(1) = -9 or -8)";
        }
    } catch (...) {
        MatDestroy(&kt);
        throw;
    }
    MatDestroy(&kt);
    return solved_local;
}

namespace {

// Collective: every rank's part of one solve. Rank 0 brings the problem and gets the result
// in the core's vertex order; the others pass nulls and get an empty matrix.
Eigen::MatrixXd solve_collectively(MPI_Comm comm, FactoredProblem* problem, const EngineOptions* options,
                                   FilterReport& report) {
    const Ranks ranks(comm);
    const auto t0 = std::chrono::steady_clock::now();
    DistributedProblem root_header;
    SparseMatrix kt;
    Eigen::VectorXd sqrt_mass;
    Eigen::MatrixXd q;
    if (problem) {
        root_header.pole_solver = options->pole_solver;
        root_header.vertices = PetscInt(problem->coordinates.rows());
        root_header.allowed_error = problem->allowed_error;
        root_header.max_iterations = problem->max_iterations;
        root_header.g = problem->g;
        sqrt_mass = problem->laplacian.mass.cwiseSqrt();
        kt = mass_normalized_stiffness(problem->laplacian);
        q = sqrt_mass.asDiagonal() * problem->coordinates;
        // Kt and q say all of it from here on. (Swapped out: a sparse matrix assigned an
        // empty one keeps its storage.)
        SparseMatrix().swap(problem->laplacian.stiffness);
        problem->laplacian.mass.resize(0);
        problem->coordinates.resize(0, 0);
    }
    const DistributedProblem header = broadcast_header(comm, problem ? &root_header : nullptr);
    const std::vector<int> owner = partition_vertices(comm, problem ? &kt : nullptr, header.vertices);
    std::vector<int> order, row_counts;
    long coupling_entries = 0;
    const long kt_entries = problem ? long(kt.nonZeros()) : 0;
    struct Communicator {
        MPI_Comm handle;
        ~Communicator() { MPI_Comm_free(&handle); }
    } engine{reversed(comm)};
    LocalRows local =
        distribute_rows(comm, engine.handle, problem ? &kt : nullptr, problem ? &q : nullptr, owner, order, row_counts, coupling_entries);
    SparseMatrix().swap(kt);
    q.resize(0, 0);
    // Under Open MPI what the process frees stays its own (measured: rank 0 kept ~470 MiB of
    // the mesh pipeline's and the distribution's freed memory at 2M vertices); given back
    // here, before the factorisation, where every rank's memory peaks.
    malloc_trim(0);
    report.seconds_assembly += seconds_since(t0);

    std::string factor_note;
    const Eigen::MatrixXd solved_local = filter_rows(engine.handle, local.kt, local.q, header, report, &factor_note);
    if (options && options->log) {
        std::string line = "distributed over " + std::to_string(ranks.size) + " rank(s)" +
                           (ranks.size > 1 ? " (PT-Scotch partition)" : "") + ": rows per rank";
        for (int c : row_counts) line += " " + std::to_string(c);
        line += "; " + format_number(100.0 * double(coupling_entries) / double(std::max(kt_entries, 1L)), 3) +
                "% of Kt's entries couple ranks" + factor_note;
        options->log->push_back(line);
    }

    // Back to rank 0, in the core's order, out of the q frame.
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> rows = solved_local;
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> gathered(ranks.rank == 0 ? header.vertices : 0, 3);
    std::vector<int> counts(row_counts);
    for (int& c : counts) c *= 3;
    MPI_Gatherv(rows.data(), int(rows.size()), MPI_DOUBLE, gathered.data(), counts.data(),
                reversed_displacements(counts).data(), MPI_DOUBLE, 0, comm);
    if (!problem) return {};
    Eigen::MatrixXd result(header.vertices, 3);
    for (PetscInt i = 0; i < header.vertices; ++i) result.row(order[size_t(i)]) = gathered.row(i) / sqrt_mass[order[size_t(i)]];
    return result;
}

} // namespace

double peak_resident_bytes() {
    std::ifstream status("/proc/self/status");
    std::string key;
    while (status >> key) {
        if (key == "VmHWM:") {
            double kib = 0;
            status >> kib;
            return kib * 1024;
        }
        status.ignore(1 << 20, '\n');
    }
    return 0;
}

Eigen::MatrixXd solve_on_all_ranks(MPI_Comm comm, FactoredProblem& problem, FilterReport& report,
                                   const EngineOptions& options) {
    // What rank 0 holds alone: the mesh read, checked and assembled as geofilter does it.
    if (options.log)
        options.log->push_back("rank 0 before the distributed solve (the mesh, its checks and K, M as in geofilter): peak " +
                               format_number(peak_resident_bytes() / (1024.0 * 1024.0), 4) + " MiB");
    int command[2] = {solve, 0};
    MPI_Bcast(command, 2, MPI_INT, 0, comm);
    return solve_collectively(comm, &problem, &options, report);
}

int serve_solves(MPI_Comm comm) {
    for (;;) {
        int command[2];
        MPI_Bcast(command, 2, MPI_INT, 0, comm);
        if (command[0] == finish) return command[1];
        if (command[0] == filter_file) {
            try {
                serve_file_filter(comm);
            } catch (const Error&) {
                // Rank 0 raised the same error and reports it once.
            }
            continue;
        }
        FilterReport unused;
        try {
            solve_collectively(comm, nullptr, nullptr, unused);
        } catch (const Error&) {
            // Rank 0 raised the same error and reports it once.
        }
    }
}

void start_file_filter(MPI_Comm comm) {
    int command[2] = {filter_file, 0};
    MPI_Bcast(command, 2, MPI_INT, 0, comm);
}

void finish_serving(MPI_Comm comm, int exit_status) {
    int command[2] = {finish, exit_status};
    MPI_Bcast(command, 2, MPI_INT, 0, comm);
}

} // namespace geofilter::mpi
