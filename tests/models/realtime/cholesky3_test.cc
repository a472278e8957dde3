// The written-out 3x3 Cholesky of VBD's vertex step (models/numerics/realtime/cholesky3.h)
// against Eigen's LLT: the same solutions on symmetric positive definite matrices,
// from well conditioned to a condition number of about 1e12, the lower triangle read
// only, and the same refusals (and a NaN refused).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <cmath>
#include <limits>
#include <random>

#include "cholesky3.h"

namespace tb {
namespace {

TEST(Cholesky3, SolvesAsEigensLltOnPositiveDefiniteMatrices) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (int trial = 0; trial < 1000; ++trial) {
    // Q diag(s) Q^T with eigenvalues spread over up to 12 decades.
    const Eigen::Matrix3d M = Eigen::Matrix3d::NullaryExpr([&](Eigen::Index, Eigen::Index) { return uniform(rng); });
    const Eigen::Matrix3d Q = Eigen::HouseholderQR<Eigen::Matrix3d>(M).householderQ();
    const double decades = 12.0 * trial / 1000;
    const Eigen::Vector3d s(1, std::pow(10.0, -decades / 2), std::pow(10.0, -decades));
    const Eigen::Matrix3d A = Q * s.asDiagonal() * Q.transpose();
    const Eigen::Vector3d b = Eigen::Vector3d::NullaryExpr([&](Eigen::Index) { return uniform(rng); });
    const Cholesky3 mine(A);
    const Eigen::LLT<Eigen::Matrix3d> eigen(A);
    ASSERT_EQ(eigen.info(), Eigen::Success) << trial;
    ASSERT_TRUE(mine.ok()) << trial;
    const Eigen::Vector3d x = mine.solve(b), y = eigen.solve(b);
    // Both backward stable: the solutions agree to the condition number times rounding.
    const double condition = 1 / s(2);
    EXPECT_LE((x - y).norm(), 1e-14 * condition * y.norm()) << trial;
    // A residual within a few times Eigen's own (both solve A's lower triangle; A is
    // symmetric to rounding only, so neither residual is zero).
    EXPECT_LE((A * x - b).norm(), 4 * (A * y - b).norm() + 1e-14 * A.norm() * x.norm()) << trial;
  }
}

TEST(Cholesky3, ReadsTheLowerTriangleOnly) {
  Eigen::Matrix3d A;
  A << 4, 0, 0,  //
      2, 5, 0,   //
      1, 3, 6;
  Eigen::Matrix3d with_upper = A;
  with_upper(0, 1) = with_upper(0, 2) = with_upper(1, 2) = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Matrix3d symmetric = A.selfadjointView<Eigen::Lower>();
  const Eigen::Vector3d b(1, -2, 3);
  const Cholesky3 mine(with_upper);
  ASSERT_TRUE(mine.ok());
  EXPECT_LE((symmetric * mine.solve(b) - b).norm(), 1e-14 * b.norm());
  EXPECT_EQ(mine.solve(b), Cholesky3(symmetric).solve(b));  // bit for bit: the same reads
}

TEST(Cholesky3, RefusesWhatIsNotPositiveDefinite) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::Matrix3d indefinite = Eigen::Vector3d(1, -1, 1).asDiagonal();
  Eigen::Matrix3d semidefinite = Eigen::Matrix3d::Ones();  // rank one
  Eigen::Matrix3d negative_corner = Eigen::Matrix3d::Identity();
  negative_corner(2, 2) = -1e-300;
  Eigen::Matrix3d with_nan = Eigen::Matrix3d::Identity();
  with_nan(2, 1) = with_nan(1, 2) = nan;
  for (const Eigen::Matrix3d& A : {indefinite, semidefinite, negative_corner}) {
    EXPECT_FALSE(Cholesky3(A).ok()) << A;
    EXPECT_NE(Eigen::LLT<Eigen::Matrix3d>(A).info(), Eigen::Success) << A;
  }
  // A NaN fails a pivot's "> 0" (VBD's vertex then waits the sweep, as for an indefinite H).
  EXPECT_FALSE(Cholesky3(with_nan).ok());
}

}  // namespace
}  // namespace tb
