// The material laws of models/numerics/materials: for every law, its stress
// against central differences of its energy and its tangent against central
// differences of its stress, the tangent's symmetry, frame indifference, zero rest
// stress, the small-strain limit and a closed form under uniaxial stretch; what
// each law does at det F <= 0; the tet element stiffness against an independent
// B^T D B and against the serial assembly; the Lame parameters and the table.
#include "material_laws.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <regex>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "arap_volume.h"
#include "lame_parameters.h"
#include "linear_elastic.h"
#include "material.h"
#include "neo_hookean.h"
#include "neo_hookean_isochoric.h"
#include "node_terms.h"
#include "stable_neo_hookean.h"
#include "xpbd_neo_hookean.h"
#include "material_law_visit.h"
#include "stiffness_assembly.h"
#include "tet_element.h"

namespace tb {
namespace {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

constexpr double kE = 3000;  // Pa, the project's default Young's modulus
/// Poisson's ratios: moderate, the project's default, nearly incompressible.
const std::vector<double> kPoisson = {0.3, 0.45, 0.49};

/// |approx - exact| / |exact| in the Frobenius norm.
template <class A, class B>
double relative(const A& approx, const B& exact) {
  return (approx - exact).norm() / exact.norm();
}

/// Deterministic numbers: uniform in [lo, hi] from std::mt19937's raw output,
/// which the standard specifies (std::uniform_real_distribution's algorithm it does not).
class Random {
 public:
  explicit Random(unsigned seed) : generator_(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * (generator_() / 4294967295.0); }
  Mat3 rotation() {
    Eigen::Quaterniond q(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    return q.normalized().toRotationMatrix();
  }

 private:
  std::mt19937 generator_;
};

/// Deformation gradients near I: I plus entries in [-0.02, 0.02] (3x3 each).
std::vector<Mat3> near_identity() {
  Random r(20180402);
  std::vector<Mat3> F;
  for (int n = 0; n < 4; ++n) {
    Mat3 A;
    for (int k = 0; k < 9; ++k) A(k) = r.uniform(-0.02, 0.02);
    F.push_back(Mat3::Identity() + A);
  }
  return F;
}

/// Deformation gradients far from I, det F > 0: R diag(s) (I + N) with a random
/// rotation R, principal stretches s in [0.6, 1.5] and a shear N, strictly upper
/// triangular with entries in [-0.4, 0.4]; and the extremes of that range.
std::vector<Mat3> far_from_identity() {
  Random r(2008628);
  std::vector<Mat3> F;
  for (int n = 0; n < 8; ++n) {
    const Vec3 s(r.uniform(0.6, 1.5), r.uniform(0.6, 1.5), r.uniform(0.6, 1.5));
    Mat3 N = Mat3::Zero();
    N(0, 1) = r.uniform(-0.4, 0.4);
    N(0, 2) = r.uniform(-0.4, 0.4);
    N(1, 2) = r.uniform(-0.4, 0.4);
    F.push_back(r.rotation() * s.asDiagonal() * (Mat3::Identity() + N));
  }
  F.push_back(Vec3(1.5, 1.5, 1.5).asDiagonal());
  F.push_back(Vec3(0.6, 0.6, 0.6).asDiagonal());
  F.push_back(Vec3(1.5, 0.6, 0.6).asDiagonal());
  F.push_back(Vec3(0.6, 1.5, 1.0).asDiagonal());
  return F;
}

std::vector<Mat3> all_samples() {
  std::vector<Mat3> F = near_identity();
  for (const Mat3& f : far_from_identity()) F.push_back(f);
  return F;
}

// Central differences with step h = 1e-5 on entries of F of order one: the
// truncation error is h^2/6 |W'''| ~ 2e-11 |W'''| and the rounding error
// eps |W| / h ~ 2e-11 |W|, both about eps^(2/3) relative for derivatives of
// order one (h ~ eps^(1/3) balances them), so even ratios |W'''| / |P| or
// |W| / |P| of 1e3 (compressed to J = 0.2, or the stable law's W(I) != 0 beside
// a small stress) stay below 1e-7: five orders under the 1e-6 tolerance, and far
// above what a wrong term (an error of order one) would give.
constexpr double kStep = 1e-5;

template <class Law>
Mat3 stress_by_differences(const Law& law, const Mat3& F) {
  Mat3 P;
  for (int k = 0; k < 9; ++k) {
    Mat3 Fp = F, Fm = F;
    Fp(k) += kStep;
    Fm(k) -= kStep;
    P(k) = (law.energy(Fp) - law.energy(Fm)) / (2 * kStep);
  }
  return P;
}

template <class Law>
Matrix9d tangent_by_differences(const Law& law, const Mat3& F) {
  Matrix9d T;
  for (int k = 0; k < 9; ++k) {
    Mat3 Fp = F, Fm = F;
    Fp(k) += kStep;
    Fm(k) -= kStep;
    T.col(k) = flatten(law.first_piola(Fp) - law.first_piola(Fm)) / (2 * kStep);
  }
  return T;
}

/// The root of r near t0 by Newton's method with a central-difference slope
/// (converges to rounding: the slope's error, ~1e-9, only slows the last digits).
double solve_scalar(const std::function<double(double)>& r, double t0) {
  double t = t0;
  for (int it = 0; it < 100; ++it) {
    const double h = 1e-7 * t;
    const double step = r(t) / ((r(t + h) - r(t - h)) / (2 * h));
    t -= step;
    if (std::abs(step) <= 1e-16 * t) break;
  }
  return t;
}

template <class Law>
struct Traits;
template <>
struct Traits<LinearElastic> {
  static constexpr const char* name = "linear";
  static constexpr bool frame_indifferent = false;
  static constexpr double small_strain_tolerance = 1e-12;
};
template <>
struct Traits<NeoHookean> {
  static constexpr const char* name = "neo_hookean";
  static constexpr bool frame_indifferent = true;
  static constexpr double small_strain_tolerance = 1e-12;
};
template <>
struct Traits<NeoHookeanIsochoric> {
  static constexpr const char* name = "neo_hookean_isochoric";
  static constexpr bool frame_indifferent = true;
  static constexpr double small_strain_tolerance = 1e-12;
};
template <>
struct Traits<StableNeoHookean> {
  static constexpr const char* name = "stable_neo_hookean";
  static constexpr bool frame_indifferent = true;
  static constexpr double small_strain_tolerance = 1e-10;
};
template <>
struct Traits<XpbdNeoHookean> {
  static constexpr const char* name = "xpbd_neo_hookean";
  static constexpr bool frame_indifferent = true;
  static constexpr double small_strain_tolerance = 1e-12;
};
template <>
struct Traits<ArapVolume> {
  static constexpr const char* name = "arap_volume";
  static constexpr bool frame_indifferent = true;
  static constexpr double small_strain_tolerance = 1e-12;
};

struct LawName {
  template <class Law>
  static std::string GetName(int) {
    return Traits<Law>::name;
  }
};

template <class Law>
class EveryLaw : public ::testing::Test {};
using Laws =
    ::testing::Types<LinearElastic, NeoHookean, NeoHookeanIsochoric, StableNeoHookean, XpbdNeoHookean, ArapVolume>;
TYPED_TEST_SUITE(EveryLaw, Laws, LawName);

TYPED_TEST(EveryLaw, StressIsTheEnergyGradient) {
  for (double nu : kPoisson) {
    const TypeParam law(lame_parameters(kE, nu));
    for (const Mat3& F : all_samples())
      EXPECT_LT(relative(stress_by_differences(law, F), law.first_piola(F)), 1e-6) << "nu " << nu << "\nF\n" << F;
  }
}

TYPED_TEST(EveryLaw, TangentIsTheStressGradient) {
  for (double nu : kPoisson) {
    const TypeParam law(lame_parameters(kE, nu));
    for (const Mat3& F : all_samples())
      EXPECT_LT(relative(tangent_by_differences(law, F), law.tangent(F)), 1e-6) << "nu " << nu << "\nF\n" << F;
  }
}

// node_stiffness (a closed form where the law's header writes one) against the
// tangent contracted by contract_tangent, and contract_tangent against the
// element stiffness's diagonal block (tet_element.h) of a tet with that gradient:
// to 1e-12 relative, rounding of sums of order |T|.
TYPED_TEST(EveryLaw, NodeStiffnessIsTheElementStiffnessDiagonalBlock) {
  Random r(2024);
  const Vec3 X[4] = {Vec3(0, 0, 0), Vec3(0.012, 0.001, 0), Vec3(0.002, 0.01, 0.001), Vec3(0.001, 0.002, 0.011)};
  const TetShape shape = tet_shape(X[0], X[1], X[2], X[3]);
  for (double nu : kPoisson) {
    const TypeParam law(lame_parameters(kE, nu));
    for (const Mat3& F : all_samples()) {
      for (int a = 0; a < 4; ++a) {
        const Vec3 g = shape.gradients.col(a);
        const Mat3 closed = law.node_stiffness(F, g), contracted = contract_tangent(law.tangent(F), g);
        EXPECT_LT(relative(closed, contracted), 1e-12) << "nu " << nu << " node " << a << "\nF\n" << F;
        const Mat3 block = tet_stiffness(shape, law, F).template block<3, 3>(3 * a, 3 * a) / shape.volume;
        EXPECT_LT(relative(contracted, block), 1e-12) << "nu " << nu << " node " << a;
      }
    }
  }
}

// node_terms (node_terms.h; a closed form sharing J, ln J and cof F where the law
// writes one, neo_hookean.h) against the law's own first_piola, node_stiffness,
// cofactor and determinant, to 1e-12 relative (rounding); and cof_g as the exact
// change of det F when the node moves by dx (F + dx g^T, the matrix determinant lemma).
TYPED_TEST(EveryLaw, NodeTermsAreTheNodesForceStiffnessAndDeterminantChange) {
  const Vec3 X[4] = {Vec3(0, 0, 0), Vec3(0.012, 0.001, 0), Vec3(0.002, 0.01, 0.001), Vec3(0.001, 0.002, 0.011)};
  const TetShape shape = tet_shape(X[0], X[1], X[2], X[3]);
  const Vec3 dx(1e-3, -2e-3, 0.5e-3);
  for (double nu : kPoisson) {
    const TypeParam law(lame_parameters(kE, nu));
    for (const Mat3& F : all_samples()) {
      for (int a = 0; a < 4; ++a) {
        const Vec3 g = shape.gradients.col(a);
        const NodeTerms t = node_terms(law, F, g);
        EXPECT_LT(relative(t.force, law.first_piola(F) * g), 1e-12) << "nu " << nu << " node " << a << "\nF\n" << F;
        EXPECT_LT(relative(t.stiffness, law.node_stiffness(F, g)), 1e-12) << "nu " << nu << " node " << a;
        EXPECT_LT(relative(t.cof_g, cofactor(F) * g), 1e-14) << "node " << a;
        EXPECT_NEAR(t.J, F.determinant(), 1e-14 * F.cwiseAbs().maxCoeff() * F.squaredNorm());
        const Mat3 moved = F + dx * g.transpose();
        EXPECT_NEAR(t.J + dx.dot(t.cof_g), moved.determinant(), 1e-12 * moved.cwiseAbs().maxCoeff() * moved.squaredNorm());
      }
    }
  }
}

TYPED_TEST(EveryLaw, TangentHasMajorSymmetry) {
  const TypeParam law(lame_parameters(kE, 0.45));
  std::vector<Mat3> samples = all_samples();
  samples.push_back(Mat3::Identity());
  for (const Mat3& F : samples) {
    const Matrix9d T = law.tangent(F);
    EXPECT_LE((T - T.transpose()).norm(), 1e-14 * T.norm()) << F;
  }
}

TYPED_TEST(EveryLaw, RestStressIsZero) {
  for (double nu : kPoisson) {
    const LameParameters lame = lame_parameters(kE, nu);
    EXPECT_LE(TypeParam(lame).first_piola(Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-12 * lame.mu) << nu;
  }
}

TYPED_TEST(EveryLaw, SmallStrainLimitIsLinearElasticity) {
  for (double nu : kPoisson) {
    const LameParameters lame = lame_parameters(kE, nu);
    const Matrix9d linear = LinearElastic(lame).tangent(Mat3::Identity());
    EXPECT_LE(relative(TypeParam(lame).tangent(Mat3::Identity()), linear), Traits<TypeParam>::small_strain_tolerance)
        << nu;
  }
}

// Uniaxial stress at small stretch recovers the given E and nu: with l - 1 = 1e-5
// and the lateral stretch t from P_22 = 0 (free lateral faces), P_11 / (l - 1) -> E
// and (1 - t) / (l - 1) -> nu, to O(l - 1) (the nonlinear terms) plus rounding
// (the stress, of order E 1e-5, is a difference of terms of order E: ~1e-11 relative).
TYPED_TEST(EveryLaw, SmallUniaxialStretchGivesYoungsModulusAndPoissonsRatio) {
  const double e = 1e-5, l = 1 + e;
  for (double nu : kPoisson) {
    const TypeParam law(lame_parameters(kE, nu));
    auto diag = [&](double t) { return Vec3(l, t, t).asDiagonal().toDenseMatrix(); };
    const double t = solve_scalar([&](double s) { return law.first_piola(diag(s))(1, 1); }, 1.0);
    EXPECT_NEAR(law.first_piola(diag(t))(0, 0) / e, kE, 1e-4 * kE) << nu;
    EXPECT_NEAR((1 - t) / e, nu, 1e-4) << nu;
  }
}

// W(R F) = W(F) and P(R F) = R P(F) for rotations R, to 1e-12 relative (near I,
// where W ~ mu 1e-4 is a difference of terms of order mu 1e-2, rounding leaves
// ~2e-13); the small-strain law charges a rigid rotation energy instead
// (eps = sym(R) - I), which is why it is not used at large rotation.
TYPED_TEST(EveryLaw, FrameIndifference) {
  Random r(37);
  for (double nu : kPoisson) {
    const TypeParam law(lame_parameters(kE, nu));
    for (const Mat3& F : all_samples()) {
      const Mat3 R = r.rotation();
      if constexpr (Traits<TypeParam>::frame_indifferent) {
        EXPECT_LE(std::abs(law.energy(R * F) - law.energy(F)), 1e-12 * std::abs(law.energy(F))) << F;
        EXPECT_LE(relative(law.first_piola(R * F), R * law.first_piola(F)), 1e-12) << F;
      } else {
        EXPECT_GT(std::abs(law.energy(R * F) - law.energy(F)), 1e-3 * law.energy(F)) << F;
      }
    }
    if constexpr (!Traits<TypeParam>::frame_indifferent) {
      const Mat3 R = Eigen::AngleAxisd(0.5, Vec3::UnitZ()).toRotationMatrix();
      EXPECT_GT(law.energy(R), 0);  // a rigid rotation of half a radian, strained
    }
  }
}

// ---- Closed forms under uniaxial stretch F = diag(l, t, t) -------------------

// Linear: eps = diag(l - 1, t - 1, t - 1). sigma_22 = 2 mu (t - 1) + lambda
// (l - 1 + 2 (t - 1)) = 0 gives t - 1 = -lambda / (2 (lambda + mu)) (l - 1)
// = -nu (l - 1); then sigma_11 = (2 mu + lambda - lambda^2 / (lambda + mu)) (l - 1)
// = mu (3 lambda + 2 mu) / (lambda + mu) (l - 1) = E (l - 1), and
// W = sigma : eps / 2 = E (l - 1)^2 / 2.
TEST(LinearElastic, UniaxialStretchClosedForm) {
  for (double nu : kPoisson)
    for (double l : {1.3, 0.7}) {
      const LinearElastic law(lame_parameters(kE, nu));
      const Mat3 F = Vec3(l, 1 - nu * (l - 1), 1 - nu * (l - 1)).asDiagonal();
      const Mat3 P = law.first_piola(F);
      EXPECT_NEAR(P(0, 0), kE * (l - 1), 1e-12 * kE);
      EXPECT_NEAR(P(1, 1), 0, 1e-12 * kE);
      EXPECT_NEAR(P(2, 2), 0, 1e-12 * kE);
      EXPECT_NEAR(law.energy(F), kE * (l - 1) * (l - 1) / 2, 1e-12 * kE);
    }
}

// Checks a law at F = diag(l, t, t) with t from P_22 = 0, solved on the closed
// form p22(l, t): the law's P_22 vanishes there, its P_11 and W equal the closed
// forms p11, w, and the off-diagonal stresses vanish; all to 1e-12 relative.
template <class Law>
void expect_uniaxial(const Law& law, double l, const std::function<double(double, double)>& p11,
                     const std::function<double(double, double)>& p22, const std::function<double(double, double)>& w) {
  const double t = solve_scalar([&](double s) { return p22(l, s); }, 1.0);
  const Mat3 F = Vec3(l, t, t).asDiagonal();
  const Mat3 P = law.first_piola(F);
  EXPECT_NEAR(P(0, 0), p11(l, t), 1e-12 * std::abs(p11(l, t))) << "l " << l << " t " << t;
  EXPECT_LE(std::abs(P(1, 1)), 1e-12 * std::abs(P(0, 0))) << "l " << l << " t " << t;
  EXPECT_LE(std::abs(P(2, 2)), 1e-12 * std::abs(P(0, 0))) << "l " << l << " t " << t;
  EXPECT_LE((P - Mat3(P.diagonal().asDiagonal())).norm(), 1e-12 * std::abs(P(0, 0)));
  EXPECT_NEAR(law.energy(F), w(l, t), 1e-12 * std::abs(w(l, t))) << "l " << l << " t " << t;
}

// Coupled neo-Hookean: J = l t^2, F^-T = diag(1/l, 1/t, 1/t), and
// P = mu F + (lambda ln J - mu) F^-T gives
//   P_11 = mu (l - 1/l) + lambda ln(J) / l,   P_22 = P_33 = mu (t - 1/t) + lambda ln(J) / t,
//   W = mu/2 (l^2 + 2 t^2 - 3) - mu ln J + lambda/2 (ln J)^2.
TEST(NeoHookean, UniaxialStretchClosedForm) {
  for (double nu : kPoisson)
    for (double l : {1.5, 0.6}) {
      const LameParameters p = lame_parameters(kE, nu);
      const double mu = p.mu, lambda = p.lambda;
      expect_uniaxial(
          NeoHookean(p), l, [&](double l, double t) { return mu * (l - 1 / l) + lambda * std::log(l * t * t) / l; },
          [&](double l, double t) { return mu * (t - 1 / t) + lambda * std::log(l * t * t) / t; },
          [&](double l, double t) {
            const double ln_J = std::log(l * t * t);
            return mu / 2 * (l * l + 2 * t * t - 3) - mu * ln_J + lambda / 2 * ln_J * ln_J;
          });
    }
}

// Isochoric split: J = l t^2, I1 = l^2 + 2 t^2, a = J^(-2/3), c = C10, k = 2/D1;
// W = c (a I1 - 3) + k/2 (J - 1)^2 and, with dJ/dl = t^2 = J/l, dJ/dF_22 = l t = J/t,
// da = -(2/3) (a/J) dJ:
//   P_11 = c (2 a l - (2/3) a I1 / l) + k (J - 1) t^2 = (2 c a / l)(l^2 - I1/3) + k (J - 1) t^2,
//   P_22 = (2 c a / t)(t^2 - I1/3) + k (J - 1) l t.
TEST(NeoHookeanIsochoric, UniaxialStretchClosedForm) {
  for (double nu : kPoisson)
    for (double l : {1.5, 0.6}) {
      const LameParameters p = lame_parameters(kE, nu);
      const double c = p.mu / 2, k = p.bulk_modulus();
      auto a = [](double l, double t) { return std::pow(l * t * t, -2.0 / 3.0); };
      auto I1 = [](double l, double t) { return l * l + 2 * t * t; };
      expect_uniaxial(
          NeoHookeanIsochoric(p), l,
          [&](double l, double t) {
            return 2 * c * a(l, t) / l * (l * l - I1(l, t) / 3) + k * (l * t * t - 1) * t * t;
          },
          [&](double l, double t) {
            return 2 * c * a(l, t) / t * (t * t - I1(l, t) / 3) + k * (l * t * t - 1) * l * t;
          },
          [&](double l, double t) { return c * (a(l, t) * I1(l, t) - 3) + k / 2 * (l * t * t - 1) * (l * t * t - 1); });
    }
}

// Stable neo-Hookean: cof diag(l, t, t) = diag(t^2, l t, l t), I1 = l^2 + 2 t^2,
// J = l t^2, b = mu' (1 - 1/(I1 + 1)); P = b F + lambda' (J - alpha) cof F gives
//   P_11 = b l + lambda' (J - alpha) t^2,   P_22 = b t + lambda' (J - alpha) l t,
//   W = mu'/2 (I1 - 3) + lambda'/2 (J - alpha)^2 - mu'/2 ln(I1 + 1),
// with mu' = 4 mu/3, lambda' = lambda + 5 mu/6, alpha = 1 + mu'/lambda' - mu'/(4 lambda').
TEST(StableNeoHookean, UniaxialStretchClosedForm) {
  for (double nu : kPoisson)
    for (double l : {1.5, 0.6}) {
      const LameParameters p = lame_parameters(kE, nu);
      const double mu = 4 * p.mu / 3, lambda = p.lambda + 5 * p.mu / 6;
      const double alpha = 1 + mu / lambda - mu / (4 * lambda);
      auto I1 = [](double l, double t) { return l * l + 2 * t * t; };
      auto b = [&](double l, double t) { return mu * (1 - 1 / (I1(l, t) + 1)); };
      expect_uniaxial(
          StableNeoHookean(p), l,
          [&](double l, double t) { return b(l, t) * l + lambda * (l * t * t - alpha) * t * t; },
          [&](double l, double t) { return b(l, t) * t + lambda * (l * t * t - alpha) * l * t; },
          [&](double l, double t) {
            const double J = l * t * t;
            return mu / 2 * (I1(l, t) - 3) + lambda / 2 * (J - alpha) * (J - alpha) - mu / 2 * std::log(I1(l, t) + 1);
          });
    }
}

// The parameters the stable law derives, and its energy at rest.
TEST(StableNeoHookean, ParametersFromLame) {
  const LameParameters p = lame_parameters(kE, 0.45);
  const StableNeoHookean law(p);
  EXPECT_DOUBLE_EQ(law.mu, 4 * p.mu / 3);
  EXPECT_DOUBLE_EQ(law.lambda, p.lambda + 5 * p.mu / 6);
  EXPECT_NEAR(law.alpha, 1 + p.mu / law.lambda, 1e-15);  // 3/4 mu' = mu
  const double w_rest = law.lambda / 2 * (1 - law.alpha) * (1 - law.alpha) - law.mu / 2 * std::log(4.0);
  EXPECT_NEAR(law.energy(Mat3::Identity()), w_rest, 1e-12 * std::abs(w_rest));
}

// ---- det F <= 0 -------------------------------------------------------------

/// A reflection, a flat element and a point reflection.
std::vector<Mat3> non_positive_J() {
  return {Vec3(1, 1, -1).asDiagonal(), Vec3(1, 1, 0).asDiagonal(), -Mat3::Identity()};
}

template <class Law>
void expect_undefined_when_inverted(const Law& law, const std::string& name) {
  for (const Mat3& F : non_positive_J()) {
    EXPECT_EQ(law.energy(F), std::numeric_limits<double>::infinity()) << F;
    EXPECT_THROW(law.first_piola(F), std::domain_error) << F;
    EXPECT_THROW(law.tangent(F), std::domain_error) << F;
    try {
      law.first_piola(F);
    } catch (const std::domain_error& e) {
      EXPECT_NE(std::string(e.what()).find(name + ": first Piola-Kirchhoff stress is undefined at det F = "),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(NeoHookean, UndefinedForNonPositiveJ) {
  expect_undefined_when_inverted(NeoHookean(lame_parameters(kE, 0.45)), "neo_hookean");
}

TEST(NeoHookean, NodeTermsUndefinedForNonPositiveJ) {
  const NeoHookean law(lame_parameters(kE, 0.45));
  for (const Mat3& F : non_positive_J()) EXPECT_THROW(node_terms(law, F, Vec3(1, 2, 3)), std::domain_error) << F;
}

TEST(NeoHookeanIsochoric, UndefinedForNonPositiveJ) {
  expect_undefined_when_inverted(NeoHookeanIsochoric(lame_parameters(kE, 0.45)), "neo_hookean_isochoric");
}

/// A law defined for det F <= 0: finite there; at the reflection diag(1, 1, -1),
/// dW/dF_33 = P_33 < 0 (the energy falls as F_33 grows back towards +1); and the
/// central differences hold at an inverted F too (smooth through J = 0).
template <class Law>
void expect_finite_when_inverted_and_pushing_back(const Law& law) {
  for (const Mat3& F : non_positive_J()) {
    EXPECT_TRUE(std::isfinite(law.energy(F))) << F;
    EXPECT_TRUE(law.first_piola(F).allFinite()) << F;
    EXPECT_TRUE(law.tangent(F).allFinite()) << F;
  }
  EXPECT_LT(law.first_piola(Vec3(1, 1, -1).asDiagonal())(2, 2), 0);
  const Mat3 F = Vec3(1.1, 0.9, -0.3).asDiagonal();
  EXPECT_LT(relative(stress_by_differences(law, F), law.first_piola(F)), 1e-6);
  EXPECT_LT(relative(tangent_by_differences(law, F), law.tangent(F)), 1e-6);
}

TEST(StableNeoHookean, FiniteWhenInvertedAndPushesBack) {
  expect_finite_when_inverted_and_pushing_back(StableNeoHookean(lame_parameters(kE, 0.45)));
}

TEST(LinearElastic, FiniteWhenInverted) {
  const LinearElastic law(lame_parameters(kE, 0.45));
  for (const Mat3& F : non_positive_J()) {
    EXPECT_TRUE(std::isfinite(law.energy(F))) << F;
    EXPECT_TRUE(law.first_piola(F).allFinite()) << F;
    EXPECT_TRUE(law.tangent(F).allFinite()) << F;
  }
}

// ---- The same law written a second way ---------------------------------------

// The neo-Hookean stress and tangent in the form the distributed solver wrote by
// hand before it used the law table: P = mu (F - F^-T) + lambda ln J F^-T and
// dP[dF] = mu dF + (mu - lambda ln J) F^-T dF^T F^-T + lambda (F^-T : dF) F^-T.
// The law's header writes them through cof F and d^2 J/dF^2.
TEST(NeoHookean, EqualsItsInverseTransposeForm) {
  Random r(6);
  for (double nu : kPoisson) {
    const LameParameters p = lame_parameters(kE, nu);
    const NeoHookean law(p);
    for (const Mat3& F : all_samples()) {
      const Mat3 F_inv_T = F.inverse().transpose();
      const double ln_J = std::log(F.determinant());
      const Mat3 P = p.mu * (F - F_inv_T) + p.lambda * ln_J * F_inv_T;
      EXPECT_LT(relative(law.first_piola(F), P), 1e-12) << F;
      Mat3 dF;
      for (int k = 0; k < 9; ++k) dF(k) = r.uniform(-1, 1);
      const Mat3 dP = p.mu * dF + (p.mu - p.lambda * ln_J) * F_inv_T * dF.transpose() * F_inv_T +
                      p.lambda * (F_inv_T.cwiseProduct(dF).sum()) * F_inv_T;
      EXPECT_LT(relative(unflatten(law.tangent(F) * flatten(dF)), dP), 1e-12) << F;
    }
  }
}

// ---- The tet element ---------------------------------------------------------

/// Tets to check the element on: a regular-ish one and random positive ones (4 rest positions each, m).
std::vector<std::array<Vec3, 4>> test_tets() {
  std::vector<std::array<Vec3, 4>> tets = {{Vec3(0, 0, 0), Vec3(0.01, 0, 0), Vec3(0, 0.01, 0), Vec3(0, 0, 0.01)}};
  Random r(11);
  while (tets.size() < 6) {
    std::array<Vec3, 4> X;
    for (Vec3& x : X) x = Vec3(r.uniform(-0.05, 0.05), r.uniform(-0.05, 0.05), r.uniform(-0.05, 0.05));
    Mat3 Dm;
    Dm << X[1] - X[0], X[2] - X[0], X[3] - X[0];
    if (Dm.determinant() < 0) std::swap(X[1], X[2]);
    if (std::abs(Dm.determinant()) > 1e-6) tets.push_back(X);  // not a sliver
  }
  return tets;
}

// The B^T D B of textbooks, computed here from scratch: shape functions from the
// 4x4 system N_a(X) = c0 + c . X with N_a(X_b) = [a = b], Voigt strains (xx, yy,
// zz, yz, xz, xy) with engineering shears, and
//   D = lambda 1 1^T + 2 mu I on the normal block, mu I on the shear block.
Eigen::Matrix<double, 12, 12> voigt_stiffness(const std::array<Vec3, 4>& X, const LameParameters& p) {
  Eigen::Matrix4d M;
  for (int a = 0; a < 4; ++a) M.row(a) << 1, X[a].transpose();
  const Eigen::Matrix4d coefficients = M.inverse();  // column a: (c0, c) of N_a
  const double volume = std::abs(M.determinant()) / 6;
  Eigen::Matrix<double, 6, 12> B = Eigen::Matrix<double, 6, 12>::Zero();
  for (int a = 0; a < 4; ++a) {
    const Vec3 g = coefficients.block<3, 1>(1, a);
    const int c = 3 * a;
    B(0, c) = g(0);
    B(1, c + 1) = g(1);
    B(2, c + 2) = g(2);
    B(3, c + 1) = g(2), B(3, c + 2) = g(1);
    B(4, c) = g(2), B(4, c + 2) = g(0);
    B(5, c) = g(1), B(5, c + 1) = g(0);
  }
  Eigen::Matrix<double, 6, 6> D = Eigen::Matrix<double, 6, 6>::Zero();
  D.topLeftCorner<3, 3>().setConstant(p.lambda);
  D.diagonal() << Vec3::Constant(p.lambda + 2 * p.mu), Vec3::Constant(p.mu);
  return volume * B.transpose() * D * B;
}

TEST(TetStiffness, LinearLawIsBtDB) {
  for (double nu : kPoisson) {
    const LameParameters p = lame_parameters(kE, nu);
    for (const auto& X : test_tets()) {
      const Eigen::Matrix<double, 12, 12> K = tet_stiffness(X[0], X[1], X[2], X[3], LinearElastic(p));
      EXPECT_LT(relative(K, voigt_stiffness(X, p)), 1e-12);
    }
  }
}

TEST(TetStiffness, SymmetricWithTheRigidModesInItsNullSpace) {
  const LameParameters p = lame_parameters(kE, 0.45);
  for (const auto& X : test_tets()) {
    const Eigen::Matrix<double, 12, 12> K = tet_stiffness(X[0], X[1], X[2], X[3], LinearElastic(p));
    EXPECT_LE((K - K.transpose()).norm(), 1e-14 * K.norm());
    for (int mode = 0; mode < 6; ++mode) {
      // Translations along e_c, then infinitesimal rotations u_a = e_c x X_a.
      const Vec3 e = Vec3::Unit(mode % 3);
      Eigen::Matrix<double, 12, 1> r;
      for (int a = 0; a < 4; ++a) r.segment<3>(3 * a) = mode < 3 ? e : Vec3(e.cross(X[a]));
      EXPECT_LE((K * r).norm(), 1e-12 * K.norm() * r.norm()) << "mode " << mode;
    }
  }
}

// Away from rest, for a nonlinear law: the internal force is the gradient of
// V W(F(x)) and the stiffness the gradient of the internal force (central
// differences in the nodal positions, step 1e-7 m on a tet of size 0.05 m: the
// same relative step as kStep).
template <class Law>
void expect_element_derivatives(const Law& law) {
  Random r(99);
  for (const auto& X : test_tets()) {
    const TetShape shape = tet_shape(X[0], X[1], X[2], X[3]);
    Eigen::Matrix<double, 3, 4> x;
    const Mat3 A = far_from_identity()[0];
    for (int a = 0; a < 4; ++a) x.col(a) = A * X[a] + Vec3(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1)) * 1e-4;
    auto energy = [&](const Eigen::Matrix<double, 3, 4>& y) {
      return shape.volume * law.energy(tet_deformation_gradient(shape, y));
    };
    auto force = [&](const Eigen::Matrix<double, 3, 4>& y) {
      return tet_internal_force(shape, law, tet_deformation_gradient(shape, y));
    };
    const double h = 1e-7;
    Eigen::Matrix<double, 12, 1> f_fd;
    Eigen::Matrix<double, 12, 12> K_fd;
    for (int k = 0; k < 12; ++k) {
      Eigen::Matrix<double, 3, 4> xp = x, xm = x;
      xp(k) += h;
      xm(k) -= h;
      f_fd(k) = (energy(xp) - energy(xm)) / (2 * h);
      K_fd.col(k) = (force(xp) - force(xm)) / (2 * h);
    }
    const Mat3 F = tet_deformation_gradient(shape, x);
    EXPECT_LT(relative(f_fd, tet_internal_force(shape, law, F)), 1e-6);
    EXPECT_LT(relative(K_fd, tet_stiffness(shape, law, F)), 1e-6);
  }
}

TEST(TetStiffness, ForceAndStiffnessAreDerivativesAwayFromRest) {
  const LameParameters p = lame_parameters(kE, 0.45);
  expect_element_derivatives(LinearElastic(p));
  expect_element_derivatives(NeoHookean(p));
  expect_element_derivatives(NeoHookeanIsochoric(p));
  expect_element_derivatives(StableNeoHookean(p));
  expect_element_derivatives(ArapVolume(p));
}

// The serial assembly (numerics/elasticity/stiffness_assembly.cc, deal.II's P1 gradients) on a
// distorted cube split into six tets equals the sum of tet_stiffness with the
// linear law: one B^T D B for both.
TEST(TetStiffness, SumsToTheSerialAssembly) {
  TetMesh mesh;
  mesh.V.resize(8, 3);
  Random r(5);
  for (int v = 0; v < 8; ++v)
    mesh.V.row(v) << 0.1 * (v & 1) + r.uniform(-0.01, 0.01), 0.1 * ((v >> 1) & 1) + r.uniform(-0.01, 0.01),
        0.1 * ((v >> 2) & 1) + r.uniform(-0.01, 0.01);
  // Kuhn's split along the diagonal 0-7: one tet per order of the three axes.
  const int axes[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  mesh.T.resize(6, 4);
  for (int t = 0; t < 6; ++t) {
    mesh.T.row(t) << 0, axes[t][0], axes[t][0] + axes[t][1], 7;
    Mat3 Dm;
    for (int k = 0; k < 3; ++k) Dm.col(k) = (mesh.V.row(mesh.T(t, k + 1)) - mesh.V.row(mesh.T(t, 0))).transpose();
    if (Dm.determinant() < 0) std::swap(mesh.T(t, 1), mesh.T(t, 2));
  }
  for (double nu : kPoisson) {
    const Eigen::MatrixXd K_serial = Eigen::MatrixXd(assemble_stiffness(mesh, kE, nu));
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(24, 24);
    const LinearElastic law(lame_parameters(kE, nu));
    for (int t = 0; t < 6; ++t) {
      auto node = [&](int k) { return Vec3(mesh.V.row(mesh.T(t, k)).transpose()); };
      const Eigen::Matrix<double, 12, 12> Ke = tet_stiffness(node(0), node(1), node(2), node(3), law);
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) K.block<3, 3>(3 * mesh.T(t, a), 3 * mesh.T(t, b)) += Ke.block<3, 3>(3 * a, 3 * b);
    }
    EXPECT_LT(relative(K, K_serial), 1e-12) << nu;
  }
}

TEST(TetShape, RejectsInvertedFlatAndNonFiniteTets) {
  const Vec3 o(0, 0, 0), x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  EXPECT_NO_THROW(tet_shape(o, x, y, z));
  EXPECT_THROW(tet_shape(o, y, x, z), std::invalid_argument);              // negative orientation
  EXPECT_THROW(tet_shape(o, x, y, Vec3(1, 1, 0)), std::invalid_argument);  // flat
  EXPECT_THROW(tet_shape(o, x, y, Vec3(0, 0, std::nan(""))), std::invalid_argument);
  const TetShape s = tet_shape(o, x, y, z);
  EXPECT_DOUBLE_EQ(s.volume, 1.0 / 6);
  EXPECT_LE(s.gradients.rowwise().sum().norm(), 1e-15);  // the N_a sum to one
}

// ---- Lame parameters and the table ---------------------------------------------

TEST(LameParameters, FromYoungsModulusAndPoissonsRatio) {
  const LameParameters p = lame_parameters(3000, 0.45);
  EXPECT_NEAR(p.mu, 3000 / 2.9, 1e-12 * p.mu);
  EXPECT_NEAR(p.lambda, 1350 / 0.145, 1e-12 * p.lambda);
  EXPECT_NEAR(p.bulk_modulus(), 3000 / (3 * (1 - 2 * 0.45)), 1e-12 * p.bulk_modulus());  // E / (3 (1 - 2 nu))
  const LameParameters from_material = lame_parameters(Material{});
  EXPECT_EQ(from_material.mu, lame_parameters(Material{}.youngs_modulus, Material{}.poisson_ratio).mu);
}

TEST(LameParameters, RejectsValuesOutsideTheirRange) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  for (double E : {0.0, -1.0, inf, nan}) {
    try {
      lame_parameters(E, 0.3);
      ADD_FAILURE() << "E = " << E << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("Young's modulus must be finite and > 0"), std::string::npos) << e.what();
    }
  }
  for (double nu : {0.5, -1.0, 0.7, -2.0, nan, inf}) {
    try {
      lame_parameters(3000, nu);
      ADD_FAILURE() << "nu = " << nu << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("Poisson's ratio must lie in (-1, 0.5)"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(lame_parameters(3000, -0.99));
  EXPECT_NO_THROW(lame_parameters(3000, 0.4999));
}

TEST(MaterialLaws, EachLawOnceWithAPlainName) {
  std::vector<std::string> names;
  for (const MaterialLawInfo& law : material_laws()) {
    EXPECT_TRUE(std::regex_match(law.name, std::regex("[a-z0-9_]+"))) << law.name;
    EXPECT_FALSE(law.description.empty()) << law.name;
    names.push_back(law.name);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"linear", "neo_hookean", "neo_hookean_isochoric", "stable_neo_hookean",
                                             "xpbd_neo_hookean", "arap_volume"}));
}

template <class Law>
void expect_entry_is(const std::string& name) {
  const MaterialLawInfo& entry = find_material_law(name);
  EXPECT_EQ(entry.name, name);
  const LameParameters p = lame_parameters(kE, 0.45);
  const Law law(p);
  const Mat3 F = far_from_identity()[1];
  EXPECT_EQ(entry.energy(F, p), law.energy(F));
  EXPECT_EQ(entry.first_piola(F, p), law.first_piola(F));
  EXPECT_EQ(entry.tangent(F, p), law.tangent(F));
  const Mat3 reflection = Vec3(1, 1, -1).asDiagonal();
  if (entry.defined_when_inverted) {
    EXPECT_TRUE(std::isfinite(entry.energy(reflection, p))) << name;
    EXPECT_TRUE(entry.first_piola(reflection, p).allFinite()) << name;
  } else {
    EXPECT_EQ(entry.energy(reflection, p), std::numeric_limits<double>::infinity()) << name;
    EXPECT_THROW(entry.first_piola(reflection, p), std::domain_error) << name;
  }
}

TEST(MaterialLaws, EntriesAreTheLaws) {
  expect_entry_is<LinearElastic>("linear");
  expect_entry_is<NeoHookean>("neo_hookean");
  expect_entry_is<NeoHookeanIsochoric>("neo_hookean_isochoric");
  expect_entry_is<StableNeoHookean>("stable_neo_hookean");
  expect_entry_is<XpbdNeoHookean>("xpbd_neo_hookean");
  expect_entry_is<ArapVolume>("arap_volume");
}

// visit_material_law reaches every law of the table, as the struct of that name.
TEST(MaterialLaws, EveryLawCanBeVisitedByName) {
  const LameParameters p = lame_parameters(kE, 0.45);
  const Mat3 F = far_from_identity()[2];
  for (const MaterialLawInfo& entry : material_laws()) {
    const double W = visit_material_law(entry.name, p, [&](const auto& law) { return law.energy(F); });
    EXPECT_EQ(W, entry.energy(F, p)) << entry.name;
  }
  EXPECT_THROW(visit_material_law("rubber", p, [](const auto&) { return 0; }), std::invalid_argument);
}

// The XPBD law's parameters (the mapping of its header) and its closed form under
// uniaxial stretch F = diag(l, t, t): cof F = diag(t^2, l t, l t), J = l t^2,
//   P_11 = mu' l + lambda' (J - alpha) t^2,   P_22 = mu' t + lambda' (J - alpha) l t,
//   W = mu'/2 (l^2 + 2 t^2 - 3) + lambda'/2 (J - alpha)^2.
TEST(XpbdNeoHookean, ParametersAndUniaxialStretchClosedForm) {
  for (double nu : kPoisson) {
    const LameParameters p = lame_parameters(kE, nu);
    const XpbdNeoHookean law(p);
    EXPECT_DOUBLE_EQ(law.mu, p.mu);
    EXPECT_DOUBLE_EQ(law.lambda, p.lambda + p.mu);
    EXPECT_DOUBLE_EQ(law.alpha, 1 + law.mu / law.lambda);
    for (double l : {1.5, 0.6}) {
      const double mu = law.mu, lambda = law.lambda, alpha = law.alpha;
      expect_uniaxial(
          law, l, [&](double l, double t) { return mu * l + lambda * (l * t * t - alpha) * t * t; },
          [&](double l, double t) { return mu * t + lambda * (l * t * t - alpha) * l * t; },
          [&](double l, double t) {
            const double J = l * t * t;
            return mu / 2 * (l * l + 2 * t * t - 3) + lambda / 2 * (J - alpha) * (J - alpha);
          });
    }
  }
}

// The ARAP-plus-volume law is what its header says it is, from its definition: R
// is a rotation and Pi has det 1; both are nearest (no rotation, no unit-determinant
// matrix nearby is closer to F: random perturbations along each set); W is
// mu |F - R|^2 + 3 lambda/2 |F - Pi|^2 and P = 2 mu (F - R) + 3 lambda (F - Pi), the
// combination PD's local step computes (pd_solve.h). Inverted F included.
TEST(ArapVolume, IsTheDistanceToRotationsAndToUnitDeterminant) {
  Random r(2014);
  const LameParameters p = lame_parameters(kE, 0.45);
  const ArapVolume law(p);
  std::vector<Mat3> samples = all_samples();
  samples.push_back(Vec3(1.1, 0.9, -0.3).asDiagonal());
  samples.push_back(r.rotation() * Vec3(1.2, 0.7, -0.5).asDiagonal() * r.rotation());
  for (const Mat3& F : samples) {
    const SignedSvd svd = signed_svd(F);
    const UnitDeterminantProjection proj = project_to_unit_determinant(svd.sigma);
    const Mat3 R = svd.U * svd.V.transpose(), Pi = svd.U * proj.d.asDiagonal() * svd.V.transpose();
    EXPECT_LE((R.transpose() * R - Mat3::Identity()).norm(), 1e-14);
    EXPECT_NEAR(R.determinant(), 1, 1e-14);
    EXPECT_NEAR(Pi.determinant(), 1, 1e-14) << F;
    EXPECT_LE((svd.U * svd.sigma.asDiagonal() * svd.V.transpose() - F).norm(), 1e-14 * F.norm());
    for (int k = 0; k < 20; ++k) {
      const Mat3 Q = Eigen::AngleAxisd(r.uniform(-0.05, 0.05), Vec3(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1)).normalized())
                         .toRotationMatrix();
      EXPECT_GE((F - R * Q).norm(), (F - R).norm() - 1e-14) << F;
      Mat3 D = Pi;
      for (int e = 0; e < 9; ++e) D(e) += r.uniform(-0.02, 0.02);
      D /= std::cbrt(D.determinant());  // back on det = 1
      EXPECT_GE((F - D).norm(), (F - Pi).norm() - 1e-14) << F;
    }
    const double W = p.mu * (F - R).squaredNorm() + 1.5 * p.lambda * (F - Pi).squaredNorm();
    EXPECT_NEAR(law.energy(F), W, 1e-12 * W) << F;
    EXPECT_LT(relative(law.first_piola(F), 2 * p.mu * (F - R) + 3 * p.lambda * (F - Pi)), 1e-12) << F;
  }
  EXPECT_EQ(law.energy(Mat3::Identity()), 0);
}

// Inverted and flat elements (R a rotation, Pi of det +1 for them too).
TEST(ArapVolume, FiniteWhenInvertedAndPushesBack) {
  expect_finite_when_inverted_and_pushing_back(ArapVolume(lame_parameters(kE, 0.45)));
}

TEST(MaterialLaws, UnknownNameListsTheKnownOnes) {
  try {
    find_material_law("neo-hookean");
    ADD_FAILURE() << "unknown name accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("unknown material law \"neo-hookean\""), std::string::npos) << what;
    for (const MaterialLawInfo& law : material_laws()) EXPECT_NE(what.find(law.name), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace tb
