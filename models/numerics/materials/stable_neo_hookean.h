// Stable neo-Hookean solid (Smith, de Goes and Kim 2018, "Stable Neo-Hookean
// Flesh Simulation", ACM TOG 37(2)): the energy with the origin barrier,
//   W(F) = mu'/2 (I1 - 3) + lambda'/2 (J - alpha)^2 - mu'/2 ln(I1 + 1),
//   I1 = tr(F^T F), J = det F,  alpha = 1 + mu'/lambda' - mu'/(4 lambda'),
// written in its own parameters mu', lambda' (the paper's mu, lambda), which its
// section 3.4 maps from the Lame parameters of the given (E, nu) by
//   mu' = 4 mu / 3,   lambda' = lambda + 5 mu / 6.
// With f = vec(F), g = vec(cof F), H_J = d^2 J/dF^2 (deformation_gradient.h):
//   P = mu' (1 - 1/(I1 + 1)) F + lambda' (J - alpha) cof F,
//   dP/dF = mu' (1 - 1/(I1 + 1)) I9 + 2 mu'/(I1 + 1)^2 f f^T + lambda' g g^T
//           + lambda' (J - alpha) H_J.
// Rest stability: P(I) = (3/4 mu' - lambda' (alpha - 1)) I = 0, which is what
// alpha's value is for (alpha must use the energy's own mu', lambda').
// Small-strain limit (worked out here, and tested): at F = I,
//   dP[H] = 3/4 mu' (H + H^T) + (lambda' - 5/8 mu') tr(H) I,
// so the mapping above gives exactly mu (H + H^T) + lambda tr(H) I, linear
// elasticity with the given (E, nu); lambda' > mu/6 > 0 for every nu in (-1, 0.5).
// Note W(I) = lambda'/2 (1 - alpha)^2 - mu'/2 ln 4 != 0: the paper's energy is not
// shifted to vanish at rest (stress and tangent do not see the constant).
//
// No logarithm of J: W, P and dP/dF are polynomial in F but for ln(I1 + 1), I1 >= 0,
// so they are finite for every F, inverted (J < 0) and flat (J = 0) elements
// included, and the stress pushes an inverted element back. The tangent is not
// positive definite everywhere; projecting it (the paper's eigensystem) is left to
// the solver that needs it.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "deformation_gradient.h"
#include "lame_parameters.h"

namespace tb {

/// The stable neo-Hookean law, in the energy's own parameters mu', lambda', alpha.
struct StableNeoHookean {
  double lambda = 0;  ///< lambda' = lambda + 5 mu / 6, Pa
  double mu = 0;      ///< mu' = 4 mu / 3, Pa
  double alpha = 1;   ///< 1 + mu'/lambda' - mu'/(4 lambda') (= 1 + mu_Lame / lambda')

  explicit StableNeoHookean(const LameParameters& lame)
      : lambda(lame.lambda + 5 * lame.mu / 6), mu(4 * lame.mu / 3), alpha(1 + mu / lambda - mu / (4 * lambda)) {}

  /// W(F), J/m^3 per reference volume, finite for every finite F (3x3).
  double energy(const Eigen::Matrix3d& F) const {
    const double I1 = F.squaredNorm(), J = F.determinant();
    return 0.5 * mu * (I1 - 3) + 0.5 * lambda * (J - alpha) * (J - alpha) - 0.5 * mu * std::log(I1 + 1);
  }

  /// P(F) (3x3, Pa), finite for every finite F.
  Eigen::Matrix3d first_piola(const Eigen::Matrix3d& F) const {
    const double I1 = F.squaredNorm(), J = F.determinant();
    return (mu * (1 - 1 / (I1 + 1))) * F + (lambda * (J - alpha)) * cofactor(F);
  }

  /// dP/dF (9x9, Pa; deformation_gradient.h's index convention), finite for every finite F.
  Matrix9d tangent(const Eigen::Matrix3d& F) const {
    const double I1 = F.squaredNorm(), J = F.determinant();
    const Vector9d f = flatten(F), g = flatten(cofactor(F));
    Matrix9d T = (2 * mu / ((I1 + 1) * (I1 + 1))) * (f * f.transpose());
    T += lambda * (g * g.transpose());
    T += (lambda * (J - alpha)) * determinant_hessian(F);
    T.diagonal().array() += mu * (1 - 1 / (I1 + 1));
    return T;
  }

  /// The tangent contracted with one node's shape gradient g (contract_tangent in
  /// deformation_gradient.h; H_J drops out): mu' (1 - 1/(I1 + 1)) |g|^2 I
  /// + 2 mu'/(I1 + 1)^2 (F g)(F g)^T + lambda' (cof F g)(cof F g)^T, positive semi-definite.
  Eigen::Matrix3d node_stiffness(const Eigen::Matrix3d& F, const Eigen::Vector3d& g) const {
    const double I1 = F.squaredNorm();
    const Eigen::Vector3d f = F * g, c = cofactor(F) * g;
    return (mu * (1 - 1 / (I1 + 1)) * g.squaredNorm()) * Eigen::Matrix3d::Identity() +
           (2 * mu / ((I1 + 1) * (I1 + 1))) * (f * f.transpose()) + lambda * (c * c.transpose());
  }
};

}  // namespace tb
