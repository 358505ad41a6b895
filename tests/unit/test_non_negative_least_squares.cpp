#include "core/solve/non_negative_least_squares.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

using namespace geofilter;

namespace {

struct Problem {
    SparseMatrix gram;
    Eigen::VectorXd rhs;
};

// The normal equations of a random least-squares problem |A a - b|^2, A of `rows` x `columns`
// (fewer rows than columns: a semi-definite gram, as crowded bumps give).
Problem random_problem(int rows, int columns, unsigned seed) {
    std::mt19937 random(seed);
    std::normal_distribution<double> normal;
    Eigen::MatrixXd a(rows, columns);
    Eigen::VectorXd b(rows);
    for (int i = 0; i < rows; ++i) {
        b[i] = normal(random);
        for (int j = 0; j < columns; ++j) a(i, j) = normal(random);
    }
    const Eigen::MatrixXd gram = a.transpose() * a;
    return {gram.sparseView(), a.transpose() * b};
}

double objective(const Problem& p, const Eigen::VectorXd& x) { return 0.5 * x.dot(p.gram * x) - p.rhs.dot(x); }

// Every subset of the unknowns taken as the free ones, solved exactly, the rest zero: the
// lowest objective among the solutions that keep their bounds (the last unknown always free
// with `free_last`).
double best_over_all_free_sets(const Problem& p, bool free_last) {
    const int n = static_cast<int>(p.rhs.size());
    const Eigen::MatrixXd dense = Eigen::MatrixXd(p.gram);
    double best = 0;  // a = 0
    for (int mask = 1; mask < (1 << n); ++mask) {
        if (free_last && !(mask >> (n - 1) & 1)) continue;
        std::vector<int> free;
        for (int i = 0; i < n; ++i)
            if (mask >> i & 1) free.push_back(i);
        const int k = static_cast<int>(free.size());
        Eigen::MatrixXd g(k, k);
        Eigen::VectorXd r(k);
        for (int i = 0; i < k; ++i) {
            r[i] = p.rhs[free[i]];
            for (int j = 0; j < k; ++j) g(i, j) = dense(free[i], free[j]);
        }
        const Eigen::VectorXd y = g.completeOrthogonalDecomposition().solve(r);
        Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
        bool keeps = true;
        for (int i = 0; i < k; ++i) {
            x[free[i]] = y[i];
            keeps &= y[i] >= -1e-12 || (free_last && free[i] == n - 1);
        }
        if (keeps) best = std::min(best, objective(p, x));
    }
    return best;
}

} // namespace

// Against every choice of free unknowns (2^10 of them): the solve reaches the least objective
// any of them reaches within the bounds, with and without a last unknown free of sign, on
// definite and semi-definite normal equations.
TEST(NonNegativeLeastSquares, ReachesTheBestOfEveryFreeSet) {
    for (unsigned seed = 0; seed < 20; ++seed)
        for (const int rows : {6, 30})
            for (const bool free_last : {false, true}) {
                SCOPED_TRACE(testing::Message() << "seed " << seed << ", rows " << rows << ", free_last " << free_last);
                const Problem p = random_problem(rows, 10, seed);
                const Eigen::VectorXd a = non_negative_solve(p.gram, p.rhs, free_last);
                for (int i = 0; i + (free_last ? 1 : 0) < 10; ++i) EXPECT_GE(a[i], 0.0);
                const double best = best_over_all_free_sets(p, free_last);
                EXPECT_NEAR(objective(p, a), best, 1e-9 * (1 + std::abs(best)));
            }
}

// A problem with hundreds of heights at their bound and hundreds above it, the shape of a
// noisy pattern's fit: the solution meets the optimality conditions (Karush-Kuhn-Tucker):
// heights non-negative, the gradient zero where a height is positive and pointing down where
// it is held at zero. Freeing one unknown per solve (the classical active set) stopped after
// its 100 solves with 73 of these conditions unmet.
TEST(NonNegativeLeastSquares, MeetsTheOptimalityConditionsWithHundredsOfUnknownsAtTheirBound) {
    const Problem p = random_problem(1500, 1000, 3);
    const Eigen::VectorXd a = non_negative_solve(p.gram, p.rhs);
    const Eigen::VectorXd gradient = p.rhs - p.gram * a;
    const double scale = p.rhs.cwiseAbs().maxCoeff();
    int positive = 0, held = 0;
    for (Eigen::Index i = 0; i < a.size(); ++i) {
        EXPECT_GE(a[i], 0.0);
        if (a[i] > 0) {
            ++positive;
            EXPECT_NEAR(gradient[i], 0.0, 1e-8 * scale) << i;
        } else {
            ++held;
            EXPECT_LE(gradient[i], 1e-8 * scale) << i;
        }
    }
    EXPECT_GT(positive, 100);
    EXPECT_GT(held, 100);
}

// More unknowns than the data determine (a gram of rank 500 among 1000 unknowns): a free set
// of the block swaps has null directions and no exact solve, and the swaps wander (alone they
// ended at an objective of +4357, worse than no heights at all). The classical active set
// takes over, and the heights end non-negative and better than the best single height.
TEST(NonNegativeLeastSquares, MoreUnknownsThanTheDataDetermineStillDescend) {
    const Problem p = random_problem(500, 1000, 3);
    const Eigen::VectorXd a = non_negative_solve(p.gram, p.rhs);
    EXPECT_GE(a.minCoeff(), 0.0);
    // At least as low as the best single height alone: -rhs_i^2 / (2 gram_ii).
    double one_height = 0;
    for (Eigen::Index i = 0; i < p.rhs.size(); ++i)
        if (p.rhs[i] > 0) one_height = std::min(one_height, -0.5 * p.rhs[i] * p.rhs[i] / p.gram.coeff(i, i));
    EXPECT_LT(objective(p, a), one_height);
}
