// The scalar reference projections (reference_projections.h) against finite
// differences and the paper's own gradient, and the SIMD kernels against the
// reference over random and degenerate configurations.
#include "reference_projections.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "constraint_batches.h"
#include "cube_generator.h"
#include "load_mapping.h"
#include "pbd_solver.h"

namespace tb::pbd {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A bending configuration: the four points, their inverse masses, the signed rest angle.
struct Bend {
  Vec3 p[4];
  double w[4];
  double rest;
};
struct Stretch {
  Vec3 p[2];
  double w[2];
  double rest;
};

/// Points (p1, p2 the hinge, p3 and p4 the wings) with dihedral angle `theta`:
/// hinge along x, wings at heights h3, h4 and feet a3, a4 along it, then a random
/// rotation and translation.
Bend hinge(double theta, double h3, double h4, double a3, double a4, std::mt19937& rng) {
  std::uniform_real_distribution<double> U(-1, 1);
  const Eigen::Quaterniond q = Eigen::Quaterniond(U(rng), U(rng), U(rng), U(rng)).normalized();
  const Vec3 t(U(rng), U(rng), U(rng));
  // Flat and unfolded (theta = 0): p3 on +y, p4 on -y. p4 turned about the hinge by theta.
  const Vec3 local[4] = {{0, 0, 0}, {1, 0, 0}, {a3, h3, 0}, {a4, -h4 * std::cos(theta), h4 * std::sin(theta)}};
  Bend b;
  for (int i = 0; i < 4; ++i) b.p[i] = q * local[i] + t;
  for (double& w : b.w) w = 1 + 0.5 * U(rng);
  b.rest = kPi * U(rng);
  return b;
}

std::vector<Bend> bending_cases() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1, 1), P(0, 1);
  std::vector<Bend> cases;
  // Random points (skipping skinny triangles, whose gradient is ill-conditioned:
  // see NearlyCollinearWings below).
  while (cases.size() < 20000) {
    Bend b;
    for (Vec3& p : b.p) p = Vec3(U(rng), U(rng), U(rng));
    const Vec3 e = b.p[1] - b.p[0];
    const double q3 = e.cross(b.p[2] - b.p[0]).norm() / (e.norm() * (b.p[2] - b.p[0]).norm());
    const double q4 = e.cross(b.p[3] - b.p[0]).norm() / (e.norm() * (b.p[3] - b.p[0]).norm());
    if (q3 < 0.05 || q4 < 0.05) continue;
    for (double& w : b.w) w = P(rng) < 0.2 ? 0.0 : 2 * P(rng);              // zero inverse masses included
    if (b.w[0] + b.w[1] + b.w[2] + b.w[3] == 0) b.w[cases.size() % 4] = 1;  // all fixed: one case below
    b.rest = kPi * U(rng);
    cases.push_back(b);
  }
  // Flat, nearly flat, folded and nearly folded dihedrals.
  for (double theta : {0.0, 1e-14, -1e-12, 1e-10, -1e-8, 1e-6, 1e-3, kPi, kPi - 1e-12, -kPi + 1e-8, kPi - 1e-4})
    for (int k = 0; k < 50; ++k) {
      Bend b = hinge(theta, 0.2 + P(rng), 0.2 + P(rng), 1.5 * U(rng), 1.5 * U(rng), rng);
      if (k % 5 == 0) b.rest = 0;      // flat at rest
      if (k % 7 == 0) b.rest = theta;  // at rest
      cases.push_back(b);
    }
  // Exactly flat in the plane z = 0 (theta = 0 or -0 exactly).
  Bend flat{{{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.25, -2, 0}}, {1, 1, 1, 1}, 0.3};
  cases.push_back(flat);
  // Degenerate: coincident hinge ends, a wing on the hinge's end, exactly collinear
  // wings, all inverse masses zero.
  Bend b = flat;
  b.p[1] = b.p[0];
  cases.push_back(b);
  b = flat;
  b.p[2] = b.p[0];
  cases.push_back(b);
  b = flat;
  b.p[3] = b.p[1];
  cases.push_back(b);
  b = flat;
  b.p[2] = Vec3(0.5, 0, 0);  // on the hinge's line
  cases.push_back(b);
  b = flat;
  b.p[3] = Vec3(3, 0, 0);  // collinear beyond p2
  cases.push_back(b);
  b = hinge(0.7, 0.5, 0.5, 0.5, 0.5, rng);
  for (double& w : b.w) w = 0;
  cases.push_back(b);
  // Only p1 free, both wings' feet at p2, flat: moving p1 cannot change the angle
  // to first order, its gradient is rounding noise (kNoiseGradient).
  b = hinge(0, 1, 1, 1, 1, rng);
  b.w[0] = 1;
  b.w[1] = b.w[2] = b.w[3] = 0;
  cases.push_back(b);
  for (int fixed = 0; fixed < 4; ++fixed) {  // all but one fixed
    b = hinge(0.7, 0.5, 0.8, 0.3, 0.6, rng);
    for (int i = 0; i < 4; ++i) b.w[i] = i == fixed ? 1.0 : 0.0;
    cases.push_back(b);
  }
  return cases;
}

std::vector<Stretch> stretch_cases() {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> U(-1, 1), P(0, 1);
  std::vector<Stretch> cases;
  for (int k = 0; k < 20000; ++k) {
    Stretch s{{Vec3(U(rng), U(rng), U(rng)), Vec3(U(rng), U(rng), U(rng))}, {2 * P(rng), 2 * P(rng)}, 2 * P(rng)};
    if (k % 5 == 0) s.w[k % 2] = 0;
    if (k % 11 == 0) s.rest = (s.p[0] - s.p[1]).norm();  // at rest
    if (k % 13 == 0) s.rest = (s.p[0] - s.p[1]).norm() * (1 + 1e-12);
    cases.push_back(s);
  }
  cases.push_back({{Vec3(1, 2, 3), Vec3(1, 2, 3)}, {1, 1}, 0.5});      // coincident
  cases.push_back({{Vec3(0, 0, 0), Vec3(1, 0, 0)}, {0, 0}, 0.5});      // both fixed
  cases.push_back({{Vec3(0, 0, 0), Vec3(1e-20, 0, 0)}, {1, 1}, 0.5});  // nearly coincident
  return cases;
}

/// The kernels' corrections of every case on `isa` in `precision`, through
/// ConstraintBatches (each case its own vertices, so all are projected from the
/// given positions).
void kernel_corrections(const std::vector<Stretch>& stretch, const std::vector<Bend>& bend, double ks, double kb,
                        BendingAngle kind, InstructionSet isa, Eigen::MatrixXd& sc, Eigen::MatrixXd& bc,
                        Precision precision = Precision::Double) {
  const Eigen::Index ns = static_cast<Eigen::Index>(stretch.size()), nb = static_cast<Eigen::Index>(bend.size());
  ConstraintSet c = build_constraints(SurfaceMesh{});  // every kind, no constraint
  KindConstraints &cs = c.of("stretch"), &cb = c.of("bending");
  cs.resize(ns);
  cb.resize(nb);
  const Eigen::Index vertices = 2 * ns + 4 * nb;
  Eigen::VectorXd w = Eigen::VectorXd::Ones(vertices);  // a constraint with all w = 0 would be dropped: keep it
  PaddedPoints x = PaddedPoints::Zero(vertices, ConstraintBatches::kPositionStride);
  for (Eigen::Index i = 0; i < ns; ++i) {
    for (int j = 0; j < 2; ++j) {
      cs.vertices(i, j) = static_cast<int>(2 * i + j);
      x.row(2 * i + j).head<3>() = stretch[static_cast<size_t>(i)].p[j];
      w(2 * i + j) = stretch[static_cast<size_t>(i)].w[j];
    }
    cs.rest(i, 0) = stretch[static_cast<size_t>(i)].rest;
  }
  for (Eigen::Index i = 0; i < nb; ++i) {
    for (int j = 0; j < 4; ++j) {
      cb.vertices(i, j) = static_cast<int>(2 * ns + 4 * i + j);
      x.row(2 * ns + 4 * i + j).head<3>() = bend[static_cast<size_t>(i)].p[j];
      w(2 * ns + 4 * i + j) = bend[static_cast<size_t>(i)].w[j];
    }
    cb.rest(i, 0) = bend[static_cast<size_t>(i)].rest;
  }
  const ConstraintBatches batches(c, w, batch_width(isa, precision), precision);
  std::vector<Eigen::MatrixXd> corrections;  // stretch, bending
  if (precision == Precision::Double) {
    batches.corrections(x.data(), {ks, kb}, {kind}, isa, corrections);
  } else {
    const Eigen::Matrix<float, -1, 4, Eigen::RowMajor> xf = x.cast<float>();
    batches.corrections(xf.data(), {ks, kb}, {kind}, isa, corrections);
  }
  sc = corrections[0];
  bc = corrections[1];
}

std::vector<InstructionSet> instruction_sets() {
  std::vector<InstructionSet> sets;
  for (InstructionSet isa : kInstructionSets)
    if (cpu_supports(isa)) sets.push_back(isa);
  return sets;
}

/// The relative error measure of this file: |a - b| / max(|b|, unit), per vector.
/// `unit` is the size the correction would have for a constraint violated by its
/// own scale (a stretch by its length, a bending by 1 rad): the constraint value C
/// is a difference of nearly equal numbers near rest, so its rounding error is
/// relative to that scale, not to C.
double relative(const Vec3& a, const Vec3& b, double unit) {
  const double scale = std::max(b.norm(), unit);
  return scale > 0 ? (a - b).norm() / scale : (a - b).norm();
}

TEST(ReferenceProjections, SimdStretchKernelsAgreeWithTheReference) {
  const std::vector<Stretch> cases = stretch_cases();
  const double k = 0.9;
  for (InstructionSet isa : instruction_sets()) {
    Eigen::MatrixXd sc, bc;
    kernel_corrections(cases, {}, k, 0.7, BendingAngle::Unsigned, isa, sc, bc);
    double worst = 0;
    for (size_t i = 0; i < cases.size(); ++i) {
      const Stretch& s = cases[i];
      Vec3 r[2];
      const bool ok = reference::project_stretch(s.p[0], s.w[0], s.p[1], s.w[1], s.rest, k, r[0], r[1]);
      const double length = (s.p[0] - s.p[1]).norm();
      for (int j = 0; j < 2; ++j) {
        const Vec3 simd = sc.row(static_cast<Eigen::Index>(i)).segment<3>(3 * j);
        if (!ok) {
          ASSERT_EQ(simd.norm(), 0.0) << name(isa) << " case " << i;
          continue;
        }
        const double unit = k * s.w[j] / (s.w[0] + s.w[1]) * std::max(length, s.rest);
        const double err = relative(simd, r[j], unit);
        worst = std::max(worst, err);
        ASSERT_LE(err, 1e-12) << name(isa) << " case " << i << " slot " << j;
      }
    }
    RecordProperty(std::string("worst_relative_error_") + name(isa), testing::PrintToString(worst));
  }
}

TEST(ReferenceProjections, SimdBendingKernelsAgreeWithTheReference) {
  const std::vector<Bend> cases = bending_cases();
  const double k = 0.7;
  for (BendingAngle kind : {BendingAngle::Unsigned, BendingAngle::Signed})
    for (InstructionSet isa : instruction_sets()) {
      Eigen::MatrixXd sc, bc;
      kernel_corrections({}, cases, 0.9, k, kind, isa, sc, bc);
      double worst = 0;
      int degenerate = 0;
      for (size_t i = 0; i < cases.size(); ++i) {
        const Bend& b = cases[i];
        Vec3 r[4];
        const bool ok = reference::project_bending(b.p[0], b.w[0], b.p[1], b.w[1], b.p[2], b.w[2], b.p[3], b.w[3],
                                                   b.rest, k, r, kind);
        double theta;
        Vec3 g[4];
        reference::dihedral_angle(b.p[0], b.p[1], b.p[2], b.p[3], theta, g);
        double denominator = 0;
        for (int j = 0; j < 4; ++j) denominator += b.w[j] * g[j].squaredNorm();
        degenerate += !ok;
        // Where the constraint itself is discontinuous, within the angle's 1e-12
        // of it, the rounding picks the side, and either side is the answer: the
        // unsigned angle's gradient flips sign at flat and at fully folded (eq. 19's
        // kinks, arccos(+-1): corrections -r), the signed angle jumps by 2 pi at
        // fully folded (C - 2 pi sign(theta)).
        Vec3 other_side[4];  // the corrections on the other side, -k C' w_j grad'_j C / denominator
        const double C = kind == BendingAngle::Signed ? theta - b.rest : std::abs(theta) - std::abs(b.rest);
        const double grad_sign = kind == BendingAngle::Unsigned && theta < 0 ? -1 : 1;
        const bool at_kink =
            kind == BendingAngle::Unsigned && (std::abs(theta) < 1e-12 || std::abs(theta) > kPi - 1e-12);
        const bool at_jump = kind == BendingAngle::Signed && std::abs(theta) > kPi - 1e-12;
        for (int j = 0; j < 4; ++j) other_side[j] = r[j];
        if (at_kink || at_jump) {
          const double C_other = at_jump ? C - 2 * kPi * (theta > 0 ? 1 : -1) : C;
          const double sign_other = at_kink ? -grad_sign : grad_sign;
          for (int j = 0; j < 4; ++j) other_side[j] = (-k * C_other * b.w[j] * sign_other / denominator) * g[j];
        }
        for (int j = 0; j < 4; ++j) {
          const Vec3 simd = bc.row(static_cast<Eigen::Index>(i)).segment<3>(3 * j);
          if (!ok) {
            ASSERT_EQ(simd.norm(), 0.0) << name(isa) << " case " << i;
            continue;
          }
          const double unit = k * b.w[j] * g[j].norm() / denominator;  // per radian of C
          const double err = std::min(relative(simd, r[j], unit), relative(simd, other_side[j], unit));
          worst = std::max(worst, err);
          ASSERT_LE(err, 1e-12) << name(isa) << " case " << i << " slot " << j << " theta " << theta;
        }
      }
      EXPECT_EQ(degenerate, 7);  // the seven degenerate cases of bending_cases(), no more
      RecordProperty(
          std::string("worst_relative_error_") + name(isa) + (kind == BendingAngle::Signed ? "_signed" : "_unsigned"),
          testing::PrintToString(worst));
    }
}

/// The kernels in single precision against the (double) reference on the
/// well-conditioned random cases: to single precision's rounding, with the same
/// error measure as above.
TEST(ReferenceProjections, BendingStepsAreEquation13ShortenedToTheirTrustRegion) {
  // constraints.h: the longest step at most q |p2 - p1|, q^2 = sum_j w_j |g_j|^2 /
  // ((sum_j w_j) max_j |g_j|^2); inside, eq. (13) itself; beyond, eq. (13) scaled
  // to reach the edge. The kernels follow the reference (the test above).
  const double k = 0.7;
  int inside = 0, shortened = 0;
  for (const Bend& b : bending_cases()) {
    double theta;
    Vec3 g[4];
    if (!reference::dihedral_angle(b.p[0], b.p[1], b.p[2], b.p[3], theta, g)) continue;
    if (std::abs(theta) > kPi - 1e-6) continue;  // the signed angle's jump: C's side is the rounding's
    Vec3 r[4];
    if (!reference::project_bending(b.p[0], b.w[0], b.p[1], b.w[1], b.p[2], b.w[2], b.p[3], b.w[3], b.rest, k, r,
                                    BendingAngle::Signed))
      continue;
    double denominator = 0, largest = 0, longest_eq13 = 0, longest = 0;
    for (int j = 0; j < 4; ++j) {
      denominator += b.w[j] * g[j].squaredNorm();
      largest = std::max(largest, g[j].squaredNorm());
    }
    Vec3 eq13[4];
    for (int j = 0; j < 4; ++j) {
      eq13[j] = (-k * (theta - b.rest) * b.w[j] / denominator) * g[j];
      longest_eq13 = std::max(longest_eq13, eq13[j].norm());
      longest = std::max(longest, r[j].norm());
    }
    const double reach =
        std::sqrt(denominator / ((b.w[0] + b.w[1] + b.w[2] + b.w[3]) * largest)) * (b.p[1] - b.p[0]).norm();
    ASSERT_LE(longest, reach * (1 + 1e-12));
    const double scale = longest_eq13 > reach ? reach / longest_eq13 : 1.0;
    (longest_eq13 > reach ? shortened : inside) += 1;
    for (int j = 0; j < 4; ++j) ASSERT_LE((r[j] - scale * eq13[j]).norm(), 1e-12 * longest_eq13 * scale + 1e-300);
  }
  EXPECT_GT(inside, 1000);  // both sides exercised: the random cases violate by up to 2 pi
  EXPECT_GT(shortened, 1000);
}

TEST(ReferenceProjections, AFreeHingeEndWhoseGradientNearlyVanishesBarelyMoves) {
  // Only p1 free, the wings' feet 1e-4 short of p2: moving p1 changes the angle by
  // 1e-4 of what moving a wing does. Eq. (13) alone would move p1 by |C| / |grad|,
  // about 1e3 hinge lengths for C = 0.1; the trust region keeps it within q |e|.
  std::mt19937 rng(21);
  Bend b = hinge(0.0, 1, 1, 1 - 1e-4, 1 - 1e-4, rng);
  b.w[0] = 1;
  b.w[1] = b.w[2] = b.w[3] = 0;
  b.rest = 0.1;
  double theta;
  Vec3 g[4];
  ASSERT_TRUE(reference::dihedral_angle(b.p[0], b.p[1], b.p[2], b.p[3], theta, g));
  const double hinge_length = (b.p[1] - b.p[0]).norm();
  ASSERT_GT(std::abs(theta - b.rest) / g[0].norm(), 100 * hinge_length);  // eq. (13)'s step
  const double q = g[0].norm() / std::max({g[1].norm(), g[2].norm(), g[3].norm()});
  ASSERT_LT(q, 1e-3);
  Vec3 r[4];
  ASSERT_TRUE(reference::project_bending(b.p[0], b.w[0], b.p[1], b.w[1], b.p[2], b.w[2], b.p[3], b.w[3], b.rest, 1.0, r,
                                         BendingAngle::Signed));
  EXPECT_NEAR(r[0].norm(), q * hinge_length, 1e-9 * q * hinge_length);
  EXPECT_GT(r[0].dot(-(theta - b.rest) * g[0]), 0);  // still down the gradient of C^2
  for (InstructionSet isa : instruction_sets()) {
    Eigen::MatrixXd sc, bc;
    kernel_corrections({}, {b}, 1.0, 1.0, BendingAngle::Signed, isa, sc, bc);
    EXPECT_NEAR(bc.row(0).head<3>().norm(), q * hinge_length, 1e-9 * q * hinge_length) << name(isa);
  }
}

TEST(ReferenceProjections, SinglePrecisionKernelsAgreeWithTheReferenceToFloatRounding) {
  std::vector<Bend> bends = bending_cases();
  bends.resize(20000);  // the random ones
  std::vector<Stretch> stretches = stretch_cases();
  stretches.resize(20000);
  const double k = 0.7;
  for (InstructionSet isa : instruction_sets()) {
    Eigen::MatrixXd sc, bc;
    kernel_corrections(stretches, bends, k, k, BendingAngle::Signed, isa, sc, bc, Precision::Single);
    double worst_stretch = 0, worst_bending = 0;
    for (size_t i = 0; i < stretches.size(); ++i) {
      const Stretch& s = stretches[i];
      Vec3 r[2];
      if (!reference::project_stretch(s.p[0], s.w[0], s.p[1], s.w[1], s.rest, k, r[0], r[1])) continue;
      for (int j = 0; j < 2; ++j) {
        const double unit = k * s.w[j] / (s.w[0] + s.w[1]) * std::max((s.p[0] - s.p[1]).norm(), s.rest);
        worst_stretch =
            std::max(worst_stretch, relative(sc.row(static_cast<Eigen::Index>(i)).segment<3>(3 * j), r[j], unit));
      }
    }
    for (size_t i = 0; i < bends.size(); ++i) {
      const Bend& b = bends[i];
      Vec3 r[4], g[4];
      double theta;
      if (!reference::project_bending(b.p[0], b.w[0], b.p[1], b.w[1], b.p[2], b.w[2], b.p[3], b.w[3], b.rest, k, r,
                                      BendingAngle::Signed) ||
          std::abs(std::abs(b.rest) - kPi) < 1e-3)
        continue;
      reference::dihedral_angle(b.p[0], b.p[1], b.p[2], b.p[3], theta, g);
      if (std::abs(theta) > kPi - 1e-3) continue;  // the signed angle's jump at folded, within float rounding
      double denominator = 0;
      for (int j = 0; j < 4; ++j) denominator += b.w[j] * g[j].squaredNorm();
      for (int j = 0; j < 4; ++j)
        worst_bending = std::max(worst_bending, relative(bc.row(static_cast<Eigen::Index>(i)).segment<3>(3 * j), r[j],
                                                         k * b.w[j] * g[j].norm() / denominator));
    }
    // Single precision rounds at 6e-8; the bending projection's chain (normals,
    // angle, gradient, denominator) loses a few bits more on skinny cases.
    EXPECT_LT(worst_stretch, 1e-5) << name(isa);
    EXPECT_LT(worst_bending, 1e-4) << name(isa);
    RecordProperty(std::string("worst_single_stretch_") + name(isa), testing::PrintToString(worst_stretch));
    RecordProperty(std::string("worst_single_bending_") + name(isa), testing::PrintToString(worst_bending));
  }
}

/// Skinny wings: the normals' lengths lose digits to cancellation in both
/// implementations, by the condition number |e| |wing| / |N|; the agreement is
/// 1e-12 times it.
TEST(ReferenceProjections, NearlyCollinearWingsAgreeToTheirConditioning) {
  std::mt19937 rng(13);
  std::vector<Bend> cases;
  for (double h : {1e-3, 1e-6, 1e-9})
    for (int k = 0; k < 100; ++k) cases.push_back(hinge(0.3, h, 0.5, 0.4, 0.6, rng));
  Eigen::MatrixXd sc, bc;
  kernel_corrections({}, cases, 0.9, 1.0, BendingAngle::Unsigned, best_instruction_set(), sc, bc);
  for (size_t i = 0; i < cases.size(); ++i) {
    const Bend& b = cases[i];
    Vec3 r[4];
    ASSERT_TRUE(reference::project_bending(b.p[0], b.w[0], b.p[1], b.w[1], b.p[2], b.w[2], b.p[3], b.w[3], b.rest, 1.0,
                                           r, BendingAngle::Unsigned));
    const Vec3 e = b.p[1] - b.p[0];
    const double condition = e.norm() * (b.p[2] - b.p[0]).norm() / e.cross(b.p[2] - b.p[0]).norm();
    for (int j = 0; j < 4; ++j) {
      const Vec3 simd = bc.row(static_cast<Eigen::Index>(i)).segment<3>(3 * j);
      EXPECT_LE((simd - r[j]).norm(), 1e-12 * condition * r[j].norm()) << "case " << i << " slot " << j;
    }
  }
}

/// Central differences of theta (reference) in every coordinate.
void numeric_gradient(Vec3 p[4], Vec3 g[4], double h = 1e-6) {
  for (int i = 0; i < 4; ++i)
    for (int d = 0; d < 3; ++d) {
      const double keep = p[i](d);
      double plus, minus;
      p[i](d) = keep + h;
      reference::dihedral_angle(p[0], p[1], p[2], p[3], plus, nullptr);
      p[i](d) = keep - h;
      reference::dihedral_angle(p[0], p[1], p[2], p[3], minus, nullptr);
      p[i](d) = keep;
      g[i](d) = (plus - minus) / (2 * h);
    }
}

TEST(ReferenceProjections, BendingGradientIsTheDerivativeAndThePapersWhereThatIsDefined) {
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> P(0, 1), U(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const double theta0 = (0.1 + 2.9 * P(rng)) * (U(rng) < 0 ? -1 : 1);  // away from flat and folded
    Bend b = hinge(theta0, 0.3 + P(rng), 0.3 + P(rng), U(rng), U(rng), rng);
    double theta;
    Vec3 g[4], fd[4], paper[4];
    ASSERT_TRUE(reference::dihedral_angle(b.p[0], b.p[1], b.p[2], b.p[3], theta, g));
    EXPECT_NEAR(theta, theta0, 1e-12);
    numeric_gradient(b.p, fd);
    ASSERT_TRUE(reference::paper_arccos_gradient(b.p[0], b.p[1], b.p[2], b.p[3], paper));
    double scale = 0;
    for (int i = 0; i < 4; ++i) scale = std::max(scale, g[i].norm());
    for (int i = 0; i < 4; ++i) {
      EXPECT_LE((g[i] - fd[i]).norm(), 1e-7 * scale) << "trial " << trial << " point " << i;
      // Eqs. (22)-(25) give the gradient of arccos(n1.n2) = |theta|.
      const Vec3 of_abs = theta < 0 ? Vec3(-g[i]) : g[i];
      EXPECT_LE((paper[i] - of_abs).norm(), 1e-12 * scale) << "trial " << trial << " point " << i;
    }
  }
}

TEST(ReferenceProjections, StretchFollowsEquations17And18) {
  Vec3 c1, c2;
  ASSERT_TRUE(reference::project_stretch(Vec3(0, 0, 0), 1.0, Vec3(2, 0, 0), 3.0, 1.0, 1.0, c1, c2));
  // C = 1, grad_p1 = (-1, 0, 0): dp1 = -(1/4)(1)(-1, 0, 0), dp2 = (3/4)(1)(-1, 0, 0).
  EXPECT_EQ(c1, Vec3(0.25, 0, 0));
  EXPECT_EQ(c2, Vec3(-0.75, 0, 0));
  EXPECT_FALSE(reference::project_stretch(Vec3(1, 1, 1), 1.0, Vec3(1, 1, 1), 1.0, 0.5, 1.0, c1, c2));
  EXPECT_EQ(c1.norm() + c2.norm(), 0.0);
}

/// Cube surface frames with the reference kernels and with the SIMD kernels: the
/// same Gauss-Seidel order, so the same motion up to rounding (which the
/// dynamics carry from frame to frame).
TEST(ReferenceProjections, SolverWithReferenceKernelsFollowsTheSimdSolver) {
  for (int domains : {1, 2}) {  // the reference follows the batches' order, domains or not
    Settings simd, ref;
    simd.bending_angle = ref.bending_angle = BendingAngle::Signed;
    simd.domains = ref.domains = domains;
    ref.kernels = Kernels::Reference;
    const SurfaceMesh s = make_cube_surface({0.1, 0.1, 6, 6, 6});
    std::vector<char> fixed(static_cast<size_t>(s.V.rows()));
    for (Eigen::Index v = 0; v < s.V.rows(); ++v) fixed[static_cast<size_t>(v)] = s.V(v, 2) == 0.0;
    const Eigen::VectorXd w = inverse_masses(s, 1000, fixed);
    Solver a(s, w, simd), b(s, w, ref);
    const Points none;
    for (Solver* solver : {&a, &b}) solver->set_loads({nearest_vertex(s.V, Vec3(0, 0, 0.1))});
    for (int f = 0; f < 100; ++f) {
      a.step({Vec3(0.3, -0.2, 1.0)}, {}, none);
      b.step({Vec3(0.3, -0.2, 1.0)}, {}, none);
    }
    const double moved = (a.positions() - s.V).cwiseAbs().maxCoeff();
    const double differ = (a.positions() - b.positions()).cwiseAbs().maxCoeff();
    EXPECT_GT(moved, 1e-3);
    EXPECT_LE(differ, 1e-12 * moved);
    RecordProperty("relative_difference_" + std::to_string(domains), testing::PrintToString(differ / moved));
    EXPECT_EQ(b.details()["instruction_set"], "scalar");
  }
}

TEST(ReferenceProjections, ReferenceKernelsOnSeveralThreadsAreAnError) {
  const std::vector<ParameterSpec> specs = parameter_specs();
  const Parameters p = resolve_parameters(specs, {{"kernels", "reference"}, {"threads", 2}}, "test");
  EXPECT_THROW(Settings::from(p), std::invalid_argument);
  EXPECT_THROW(resolve_parameters(specs, {{"kernels", "scalar"}}, "test"), std::invalid_argument);
  EXPECT_THROW(resolve_parameters(specs, {{"threads", 0}}, "test"), std::invalid_argument);
  EXPECT_THROW(resolve_parameters(specs, {{"threads", 1.5}}, "test"), std::invalid_argument);
  EXPECT_THROW(Settings::from(resolve_parameters(specs, {{"kernels", "reference"}, {"precision", "single"}}, "test")),
               std::invalid_argument);
  EXPECT_THROW(resolve_parameters(specs, {{"precision", "half"}}, "test"), std::invalid_argument);
  EXPECT_THROW(resolve_parameters(specs, {{"instruction_set", "neon"}}, "test"), std::invalid_argument);
  EXPECT_EQ(Settings::from(resolve_parameters(specs, {{"instruction_set", "sse2"}}, "test")).instruction_set,
            InstructionSet::Sse2);
}

}  // namespace
}  // namespace tb::pbd
