// As-rigid-as-possible with a volume term, the solid of Projective Dynamics
// (Bouaziz, Martin, Liu, Kavan and Pauly 2014, section 5, "strain" and "volume"
// constraints of a tet, with the bounds of both at 1): the squared distances of F
// to the rotations and to the matrices of unit determinant,
//   W(F) = mu |F - R(F)|^2 + 3 lambda / 2 |F - Pi(F)|^2,
// R(F) the nearest rotation, Pi(F) the nearest matrix with det = 1 (each a PD
// projection, so PD's local/global iteration minimises this energy exactly:
// numerics/realtime/pd_solve.h). With F = U diag(sigma) V^T (signed_svd.h),
// R = U V^T and Pi = U diag(d) V^T, d the point of the surface d1 d2 d3 = 1 nearest
// to sigma: by Lagrange, d_i - sigma_i = m / d_i, so
//   d_i = (sigma_i + s_i) / 2,   s_i = sqrt(sigma_i^2 + 4 m),   sum_i ln d_i = 0,
// one equation for the multiplier m (solved below by safeguarded Newton: its left
// side increases with m). In sigma, with g_i = dW/dsigma_i:
//   W = mu sum (sigma_i - 1)^2 + k/2 sum (m / d_i)^2,   k = 3 lambda,
//   g_i = 2 mu (sigma_i - 1) - k m / d_i,   P = U diag(g) V^T,
//   d^2 W / dsigma^2 = 2 mu I + k (I - dd/dsigma),
//   dd/dsigma = diag(d_i / s_i) - (1/s)(1/s)^T / sum_j 1/(d_j s_j)
// (implicit differentiation of the two conditions above), and dP/dF from these and,
// per pair i != j, the twist and flip quotients (Teran, Sifakis, Irving and Fedkiw
// 2005, "Robust quasistatic finite elements and flesh simulation", section 5)
//   (g_i - g_j)/(sigma_i - sigma_j) = 2 mu + k (1 - (1 + (sigma_i + sigma_j)/(s_i + s_j)) / 2),
//   (g_i + g_j)/(sigma_i + sigma_j),
// the first written without the difference quotient, so equal stretches (the rest
// state) need no limit; the second is singular only at sigma_i + sigma_j = 0, a flat
// or inverted element, where R itself is not differentiable (clamped there).
// Small-strain limit: at F = I, m = 0, d = s = (1, 1, 1), d^2 W/dsigma^2 = 2 mu I
// + lambda 1 1^T, twist 2 mu, flip 0: dP[H] = mu (H + H^T) + lambda tr(H) I, linear
// elasticity with the given (E, nu) (|F - Pi|^2 ~ tr(H)^2 / 3 near I, hence k = 3 lambda).
//
// Finite for every F: an inverted element has sigma_3 < 0, its R stays a rotation and
// its Pi has det +1, so both terms push it back. Isotropic and frame-indifferent:
// W(Q F Q') = W(F) for rotations Q, Q'.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "deformation_gradient.h"
#include "lame_parameters.h"
#include "signed_svd.h"

namespace tb {

/// The nearest point d to sigma (signed, as signed_svd gives it) on d1 d2 d3 = 1,
/// with the multiplier m (d_i - sigma_i = m / d_i) and s_i = sqrt(sigma_i^2 + 4 m).
struct UnitDeterminantProjection {
  Eigen::Vector3d d, s;
  double m = 0;
};

/// As above, for sigma_1 >= sigma_2 > 0 (the signed SVD of a non-degenerate F).
inline UnitDeterminantProjection project_to_unit_determinant(const Eigen::Vector3d& sigma) {
  UnitDeterminantProjection p;
  // d_i > 0 needs m > -sigma_i^2 / 4 where sigma_i > 0 and m > 0 where sigma_i <= 0.
  double lo = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) lo = std::max(lo, sigma(i) > 0 ? -sigma(i) * sigma(i) / 4 : 0.0);
  auto at = [&](double m, double& slope) {  // sum ln d_i(m), and its derivative
    double g = 0;
    slope = 0;
    for (int i = 0; i < 3; ++i) {
      p.s(i) = std::sqrt(std::max(sigma(i) * sigma(i) + 4 * m, 0.0));
      // The form without cancellation: (sigma + s) / 2 = 2 m / (s - sigma).
      p.d(i) = sigma(i) >= 0 ? (sigma(i) + p.s(i)) / 2 : 2 * m / (p.s(i) - sigma(i));
      g += std::log(p.d(i));
      slope += 1 / (p.d(i) * p.s(i));
    }
    return g;
  };
  double slope = 0, hi = std::max(lo, 0.0) + 1;
  while (!(at(hi, slope) > 0)) hi = 2 * hi + 1;
  // Safeguarded Newton on the increasing sum_i ln d_i(m), bracketed by [a, hi];
  // |sum ln d_i| at 1e-15 is its rounding, m then within ~1e-16 of the root.
  double m = lo < 0 ? 0 : (lo + hi) / 2, a = lo;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double g = at(m, slope);
    if (std::abs(g) <= 1e-15) break;
    (g < 0 ? a : hi) = m;
    double next = m - g / slope;
    if (!(next > a && next < hi)) next = (a + hi) / 2;
    const bool converged = std::abs(next - m) <= 4e-16 * std::max(std::abs(m), 1.0);
    m = next;
    if (converged) break;
  }
  at(m, slope);
  p.m = m;
  return p;
}

/// The ARAP-plus-volume law: mu |F - R|^2 + k/2 |F - Pi|^2, its parameters from the
/// Lame parameters (mu, k = 3 lambda).
struct ArapVolume {
  double mu = 0;  ///< Pa: the rotations' weight is 2 mu
  double k = 0;   ///< 3 lambda, Pa: the unit-determinant projection's weight

  explicit ArapVolume(const LameParameters& lame) : mu(lame.mu), k(3 * lame.lambda) {}

  /// W(F), J/m^3 per reference volume, finite for every finite F (3x3).
  double energy(const Eigen::Matrix3d& F) const {
    const SignedSvd svd = signed_svd(F);
    const UnitDeterminantProjection p = project_to_unit_determinant(svd.sigma);
    return mu * (svd.sigma - Eigen::Vector3d::Ones()).squaredNorm() +
           0.5 * k * (p.m * p.d.cwiseInverse()).squaredNorm();
  }

  /// P(F) = 2 mu (F - R) + k (F - Pi) (3x3, Pa).
  Eigen::Matrix3d first_piola(const Eigen::Matrix3d& F) const {
    const SignedSvd svd = signed_svd(F);
    return svd.U * stress_in_sigma(svd.sigma, project_to_unit_determinant(svd.sigma)).asDiagonal() * svd.V.transpose();
  }

  /// dP/dF (9x9, Pa; deformation_gradient.h's index convention).
  Matrix9d tangent(const Eigen::Matrix3d& F) const {
    const SignedSvd svd = signed_svd(F);
    const Eigen::Vector3d& x = svd.sigma;
    const UnitDeterminantProjection p = project_to_unit_determinant(x);
    const Eigen::Vector3d g = stress_in_sigma(x, p), inv_s = p.s.cwiseInverse();
    double weight = 0;
    for (int i = 0; i < 3; ++i) weight += 1 / (p.d(i) * p.s(i));
    Eigen::Matrix3d dd = -(inv_s * inv_s.transpose()) / weight;
    dd.diagonal() += p.d.cwiseProduct(inv_s);
    const Eigen::Matrix3d scaling = 2 * mu * Eigen::Matrix3d::Identity() + k * (Eigen::Matrix3d::Identity() - dd);
    // In U^T dF V coordinates: the scaling block on the diagonal entries, a 2x2 block
    // [[a, b], [b, a]] on each off-diagonal pair (i, j), (j, i).
    Matrix9d C = Matrix9d::Zero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) C(i + 3 * i, j + 3 * j) = scaling(i, j);
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j) {
        const double twist = 2 * mu + k * (1 - (1 + (x(i) + x(j)) / (p.s(i) + p.s(j))) / 2);
        const double flip = (g(i) + g(j)) / std::max(x(i) + x(j), 1e-12);
        const double a = (twist + flip) / 2, b = (twist - flip) / 2;
        C(i + 3 * j, i + 3 * j) = C(j + 3 * i, j + 3 * i) = a;
        C(i + 3 * j, j + 3 * i) = C(j + 3 * i, i + 3 * j) = b;
      }
    // vec(U X V^T) = (V kron U) vec(X).
    Matrix9d K;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) K.block<3, 3>(3 * a, 3 * b) = svd.V(a, b) * svd.U;
    return K * C * K.transpose();
  }

  /// The tangent contracted with one node's shape gradient g (contract_tangent).
  Eigen::Matrix3d node_stiffness(const Eigen::Matrix3d& F, const Eigen::Vector3d& g) const {
    return contract_tangent(tangent(F), g);
  }

 private:
  /// dW/dsigma_i = 2 mu (sigma_i - 1) + k (sigma_i - d_i), with sigma_i - d_i = -m / d_i.
  Eigen::Vector3d stress_in_sigma(const Eigen::Vector3d& sigma, const UnitDeterminantProjection& p) const {
    return 2 * mu * (sigma - Eigen::Vector3d::Ones()) - k * p.m * p.d.cwiseInverse();
  }
};

}  // namespace tb
