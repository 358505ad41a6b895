#include "core/solve/non_negative_least_squares.h"

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <vector>

namespace geofilter {

Eigen::VectorXd non_negative_solve(const SparseMatrix& gram, const Eigen::VectorXd& rhs, bool free_last) {
    const Eigen::Index n = rhs.size();
    Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
    if (n == 0) return a;
    const Eigen::VectorXd diagonal = gram.diagonal();
    const double largest = std::max(diagonal.maxCoeff(), 1e-300);
    const auto usable = [&](Eigen::Index i) { return diagonal[i] > 1e-12 * largest; };
    std::vector<bool> free(static_cast<size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i) free[i] = usable(i);
    constexpr int backup_after = 3;  // Kim & Park's p
    Eigen::Index fewest_infeasible = n + 1;
    int chances = backup_after;
    bool swap_in_blocks = true;
    // A pivot of the free set's factor this small (the null direction's guard is 1e-12) is
    // singular to the solve's rounding.
    constexpr double singular_pivot = 1e-10;
    for (int round = 0; round < 100; ++round) {
        std::vector<Eigen::Index> at(static_cast<size_t>(n), -1), index;
        for (Eigen::Index i = 0; i < n; ++i)
            if (free[i]) {
                at[i] = static_cast<Eigen::Index>(index.size());
                index.push_back(i);
            }
        a.setZero();
        if (!index.empty()) {
            std::vector<Eigen::Triplet<double>> entries;
            for (Eigen::Index i : index) {
                for (SparseMatrix::InnerIterator it(gram, i); it; ++it)
                    if (at[it.row()] >= 0) entries.emplace_back(at[it.row()], at[i], it.value());
                entries.emplace_back(at[i], at[i], 1e-12 * largest);  // a null direction stays at zero
            }
            SparseMatrix sub(static_cast<Eigen::Index>(index.size()), static_cast<Eigen::Index>(index.size()));
            sub.setFromTriplets(entries.begin(), entries.end());
            Eigen::VectorXd b(static_cast<Eigen::Index>(index.size()));
            for (size_t k = 0; k < index.size(); ++k) b[static_cast<Eigen::Index>(k)] = rhs[index[k]];
            const Eigen::SimplicialLDLT<SparseMatrix> factor(sub);
            const Eigen::VectorXd x = factor.solve(b);
            // A free set with a null direction (more unknowns than the data determine) has
            // no exact solve: the swaps then wander, so the rest is the classical way.
            if (swap_in_blocks && factor.vectorD().minCoeff() < singular_pivot * largest) swap_in_blocks = false;
            for (size_t k = 0; k < index.size(); ++k) a[index[k]] = x[static_cast<Eigen::Index>(k)];
        }
        // Infeasible: free and negative, or held at zero and asking to grow.
        const Eigen::VectorXd gradient = rhs - gram * a;
        std::vector<Eigen::Index> infeasible;
        for (Eigen::Index i = 0; i < n - (free_last ? 1 : 0); ++i)
            if (free[i] ? a[i] < 0
                        : usable(i) && gradient[i] > 1e-9 * std::sqrt(diagonal[i] * largest))
                infeasible.push_back(i);
        if (infeasible.empty()) break;
        if (!swap_in_blocks) {
            // Lawson & Hanson: hold every free unknown that came out negative; else free the
            // held one whose gradient asks most to grow.
            std::vector<Eigen::Index> negative;
            Eigen::Index grow = -1;
            for (Eigen::Index i : infeasible)
                if (free[i]) {
                    negative.push_back(i);
                } else if (grow < 0 || gradient[i] > gradient[grow]) {
                    grow = i;
                }
            if (negative.empty()) {
                free[grow] = true;
            } else {
                for (Eigen::Index i : negative) free[i] = false;
            }
            continue;
        }
        if (static_cast<Eigen::Index>(infeasible.size()) < fewest_infeasible) {
            fewest_infeasible = static_cast<Eigen::Index>(infeasible.size());
            chances = backup_after;
        } else if (chances > 0) {
            --chances;
        } else {
            infeasible = {infeasible.back()};
        }
        for (Eigen::Index i : infeasible) free[i] = !free[i];
    }
    if (free_last) {
        const double last = a[n - 1];
        a = a.cwiseMax(0.0);
        a[n - 1] = last;
        return a;
    }
    return a.cwiseMax(0.0);
}

} // namespace geofilter
