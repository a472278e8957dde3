// The Woodbury solve with K - U U^T on K's factor (low_rank_downdate.h) against a
// dense solve of K - U U^T itself: definite and indefinite, one right-hand side and
// many, and a singular K - U U^T refused.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "low_rank_downdate.h"

namespace tb {
namespace {

/// A symmetric positive definite n x n matrix with eigenvalues from 1 to 10 (seeded).
Eigen::MatrixXd definite_matrix(int n) {
  std::srand(7);
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(A);
  const Eigen::MatrixXd Q = qr.householderQ();
  const Eigen::VectorXd eigenvalues = Eigen::VectorXd::LinSpaced(n, 1, 10);
  return Q * eigenvalues.asDiagonal() * Q.transpose();
}

/// Solves with K - U U^T by the downdate on K's dense Cholesky factor; the negative
/// eigenvalue count it reports is compared with the dense eigenvalues'.
void expect_equals_dense(const Eigen::MatrixXd& K, const Eigen::MatrixXd& U) {
  const Eigen::LLT<Eigen::MatrixXd> factor(K);
  ASSERT_EQ(factor.info(), Eigen::Success);
  LowRankDowndate downdate;
  ASSERT_TRUE(downdate.prepare(U, factor.solve(U)));
  EXPECT_EQ(downdate.rank(), U.cols());
  const Eigen::MatrixXd downdated = K - U * U.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(downdated);
  EXPECT_EQ(downdate.negative_eigenvalues(), (eigen.eigenvalues().array() < 0).count());

  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(K.rows(), 3);
  Eigen::MatrixXd X = factor.solve(B);
  downdate.apply(X);
  const Eigen::MatrixXd expected = downdated.fullPivLu().solve(B);
  EXPECT_LT((X - expected).norm() / expected.norm(), 1e-12);
  Eigen::VectorXd x = factor.solve(B.col(1));
  downdate.apply(x);
  EXPECT_LT((x - expected.col(1)).norm() / expected.col(1).norm(), 1e-12);
}

TEST(LowRankDowndate, EqualsTheDenseSolveWhereTheDowndateStaysDefinite) {
  const Eigen::MatrixXd K = definite_matrix(40);
  const Eigen::MatrixXd U = 0.2 * Eigen::MatrixXd::Random(40, 6);  // |U U^T| well below K's smallest eigenvalue 1
  expect_equals_dense(K, U);
}

TEST(LowRankDowndate, EqualsTheDenseSolveWhereTheDowndateMakesItIndefinite) {
  const Eigen::MatrixXd K = definite_matrix(40);
  Eigen::MatrixXd U = Eigen::MatrixXd::Zero(40, 4);
  // Two columns larger than K: two negative eigenvalues at least.
  U.col(0) = 5 * Eigen::VectorXd::Unit(40, 3);
  U.col(1) = 5 * Eigen::VectorXd::Unit(40, 17);
  U.col(2) = 0.3 * Eigen::VectorXd::Random(40);
  U.col(3) = 0.3 * Eigen::VectorXd::Random(40);
  const Eigen::LLT<Eigen::MatrixXd> factor(K);
  LowRankDowndate downdate;
  ASSERT_TRUE(downdate.prepare(U, factor.solve(U)));
  EXPECT_GE(downdate.negative_eigenvalues(), 2);
  expect_equals_dense(K, U);
}

TEST(LowRankDowndate, NoTermLeavesTheSolveAsItIs) {
  const Eigen::MatrixXd K = definite_matrix(10);
  const Eigen::LLT<Eigen::MatrixXd> factor(K);
  LowRankDowndate downdate;
  ASSERT_TRUE(downdate.prepare(Eigen::MatrixXd(10, 0), Eigen::MatrixXd(10, 0)));
  Eigen::VectorXd x = factor.solve(Eigen::VectorXd::Ones(10));
  const Eigen::VectorXd before = x;
  downdate.apply(x);
  EXPECT_EQ(x, before);
  EXPECT_EQ(downdate.rank(), 0);
  EXPECT_EQ(downdate.negative_eigenvalues(), 0);
  // clear() after a term: the solve is K's again.
  ASSERT_TRUE(downdate.prepare(Eigen::MatrixXd::Ones(10, 1), factor.solve(Eigen::MatrixXd::Ones(10, 1))));
  downdate.clear();
  x = before;
  downdate.apply(x);
  EXPECT_EQ(x, before);
  EXPECT_EQ(downdate.rank(), 0);
}

TEST(LowRankDowndate, ASingularDowndateIsRefused) {
  // K = I, U = e_2: K - U U^T has a zero eigenvalue, and so has C = 1 - 1.
  const Eigen::MatrixXd K = Eigen::MatrixXd::Identity(5, 5);
  const Eigen::MatrixXd U = Eigen::VectorXd::Unit(5, 2);
  LowRankDowndate downdate;
  EXPECT_FALSE(downdate.prepare(U, U));
}

}  // namespace
}  // namespace tb
