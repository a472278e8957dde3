// Constraint gradients against central finite differences, and single-constraint
// projections.
#include "constraints.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <functional>
#include <random>

namespace tb::pbd {
namespace {

using Fn = std::function<double(const Vec3 p[4])>;

/// Central differences of f with respect to every coordinate of p[0..n).
void numeric_gradient(const Fn& f, Vec3 p[4], int n, Vec3 g[4], double h = 1e-6) {
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) {
      const double keep = p[i](d);
      p[i](d) = keep + h;
      const double fp = f(p);
      p[i](d) = keep - h;
      const double fm = f(p);
      p[i](d) = keep;
      g[i](d) = (fp - fm) / (2 * h);
    }
}

double max_relative_error(const Vec3 a[4], const Vec3 b[4], int n) {
  double err = 0, scale = 0;
  for (int i = 0; i < n; ++i) {
    err = std::max(err, (a[i] - b[i]).cwiseAbs().maxCoeff());
    scale = std::max(scale, b[i].cwiseAbs().maxCoeff());
  }
  return err / scale;
}

TEST(StretchConstraint, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int trial = 0; trial < 100; ++trial) {
    Vec3 p[4] = {{U(rng), U(rng), U(rng)}, {U(rng), U(rng), U(rng)}, Vec3::Zero(), Vec3::Zero()};
    if ((p[0] - p[1]).norm() < 0.1) continue;
    Vec3 g[4], fd[4];
    stretch_gradient(p[0], p[1], g[0], g[1]);
    numeric_gradient([](const Vec3 q[4]) { return stretch_constraint(q[0], q[1], 0.3); }, p, 2, fd);
    EXPECT_LT(max_relative_error(g, fd, 2), 1e-6) << "trial " << trial;
  }
}

TEST(StretchConstraint, ProjectionRemovesViolationExactly) {
  const Vec3 a(0, 0, 0), b(2, 0, 0);
  Vec3 ca, cb;
  ASSERT_TRUE(project_stretch(a, 1.0, b, 3.0, 1.0, 1.0, ca, cb));
  EXPECT_NEAR(stretch_constraint(a + ca, b + cb, 1.0), 0.0, 1e-15);
  // Corrections are split by inverse mass (eqs. 17-18) and conserve momentum.
  EXPECT_NEAR((1.0 / 1.0) * 0 + ca.norm() * 3.0, cb.norm() * 1.0 * 1.0, 1e-15);
  EXPECT_NEAR((ca / 1.0 + cb / 3.0).norm(), 0.0, 1e-15);
}

TEST(StretchConstraint, FixedOrCoincidentPointsDoNothing) {
  Vec3 ca, cb;
  EXPECT_FALSE(project_stretch(Vec3(0, 0, 0), 0, Vec3(1, 0, 0), 0, 0.5, 1, ca, cb));
  EXPECT_FALSE(project_stretch(Vec3(1, 1, 1), 1, Vec3(1, 1, 1), 1, 0.5, 1, ca, cb));
  EXPECT_TRUE(ca.isZero() && cb.isZero());
}

TEST(BendingConstraint, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  int tested = 0;
  for (int trial = 0; trial < 400 && tested < 100; ++trial) {
    Vec3 p[4] = {
        {U(rng), U(rng), U(rng)}, {U(rng), U(rng), U(rng)}, {U(rng), U(rng), U(rng)}, {U(rng), U(rng), U(rng)}};
    const double angle = normal_angle(p[0], p[1], p[2], p[3]);
    // Non-degenerate: away from flat/folded (arccos is not differentiable there)
    // and from thin triangles.
    if (angle < 0.2 || angle > M_PI - 0.2) continue;
    if ((p[1] - p[0]).cross(p[2] - p[0]).norm() < 0.2 || (p[1] - p[0]).cross(p[3] - p[0]).norm() < 0.2) continue;
    Vec3 g[4], fd[4];
    ASSERT_TRUE(bending_gradient(p[0], p[1], p[2], p[3], g));
    numeric_gradient([](const Vec3 q[4]) { return bending_constraint(q[0], q[1], q[2], q[3], 0.4); }, p, 4, fd);
    EXPECT_LT(max_relative_error(g, fd, 4), 1e-6) << "trial " << trial;
    ++tested;
  }
  EXPECT_EQ(tested, 100);
}

TEST(BendingConstraint, SignedAngleGradientMatchesFiniteDifferencesThroughFlat) {
  // The signed angle is smooth through the flat configuration, so test there too.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int trial = 0; trial < 100; ++trial) {
    Vec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {0.4 + 0.2 * U(rng), 1, 0.3 * U(rng)}, {0.5 + 0.2 * U(rng), -1, 0.3 * U(rng)}};
    p[0] += 0.05 * Vec3(U(rng), U(rng), U(rng));
    Vec3 g[4], fd[4];
    ASSERT_TRUE(signed_angle_gradient(p[0], p[1], p[2], p[3], g));
    numeric_gradient([](const Vec3 q[4]) { return signed_normal_angle(q[0], q[1], q[2], q[3]); }, p, 4, fd);
    EXPECT_LT(max_relative_error(g, fd, 4), 1e-6) << "trial " << trial;
    EXPECT_NEAR(std::abs(signed_normal_angle(p[0], p[1], p[2], p[3])), normal_angle(p[0], p[1], p[2], p[3]), 1e-15);
  }
}

TEST(BendingConstraint, ProjectionReducesViolationToFirstOrder) {
  // A small violation delta: after one projection the residual is O(delta^2).
  const Vec3 p1(0, 0, 0), p2(1, 0, 0), p3(0.4, 1, 0);
  for (double delta : {1e-2, 1e-3}) {
    const Vec3 p4(0.5, -1, delta);  // folded slightly out of plane
    const double c0 = bending_constraint(p1, p2, p3, p4, 0.0);
    Vec3 corr[4];
    ASSERT_TRUE(project_bending(p1, 1, p2, 1, p3, 1, p4, 1, 0.0, 1.0, corr));
    const double c1 = bending_constraint(p1 + corr[0], p2 + corr[1], p3 + corr[2], p4 + corr[3], 0.0);
    EXPECT_LT(std::abs(c1), 0.05 * std::abs(c0)) << "delta " << delta;
    // The signed variant: from a rest angle of 0.2 rad to a violation of delta.
    const double rest = 0.2;
    const Vec3 q4 = p4 + Vec3(0, 0, 0);
    const double s0 = signed_normal_angle(p1, p2, p3, q4) - rest;
    ASSERT_TRUE(project_bending(p1, 1, p2, 1, p3, 1, q4, 1, rest, 1.0, corr, BendingAngle::Signed));
    const double s1 = signed_normal_angle(p1 + corr[0], p2 + corr[1], p3 + corr[2], q4 + corr[3]) - rest;
    EXPECT_LT(std::abs(s1), 0.05 * std::abs(s0)) << "signed, delta " << delta;
  }
}

TEST(BendingConstraint, NoNanWhenFlatFoldedOrDegenerate) {
  Vec3 corr[4];
  const Vec3 p1(0, 0, 0), p2(1, 0, 0);
  // Coplanar unfolded (angle 0), folded onto itself (angle pi), degenerate wing.
  for (const Vec3& p4 : {Vec3(0.5, -1, 0), Vec3(0.5, 1, 0), Vec3(2, 0, 0)}) {
    project_bending(p1, 1, p2, 1, Vec3(0.5, 1, 0), 1, p4, 1, 0.3, 1.0, corr);
    for (const auto& c : corr) EXPECT_TRUE(c.allFinite());
    EXPECT_TRUE(std::isfinite(bending_constraint(p1, p2, Vec3(0.5, 1, 0), p4, 0.3)));
  }
  EXPECT_NEAR(normal_angle(p1, p2, Vec3(0.5, 1, 0), Vec3(0.5, -1, 0)), 0.0, 1e-12);
  EXPECT_NEAR(normal_angle(p1, p2, Vec3(0.5, 1, 0), Vec3(0.5, 1, 1e-16)), M_PI, 1e-6);
}

TEST(Stiffness, IterationCorrection) {
  EXPECT_DOUBLE_EQ(stiffness_per_iteration(0.5, 1), 0.5);
  // n sweeps at k' leave (1-k')^n = 1-k of the violation.
  EXPECT_NEAR(std::pow(1 - stiffness_per_iteration(0.3, 10), 10), 0.7, 1e-12);
  EXPECT_DOUBLE_EQ(stiffness_per_iteration(1.0, 10), 1.0);
}

}  // namespace
}  // namespace tb::pbd
