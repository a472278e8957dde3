// The neo-Hookean energy of volumetric XPBD (Macklin and Mueller 2021, "A
// Constraint-based Formulation of Stable Neo-Hookean Materials", MIG 2021):
// the stable neo-Hookean energy without its origin barrier, written as the sum of
// a deviatoric and a hydrostatic constraint energy,
//   W(F) = mu'/2 (I1 - 3) + lambda'/2 (J - alpha)^2,   alpha = 1 + mu'/lambda',
//   C_D = sqrt(I1) (compliance 1/mu'),   C_H = J - alpha (compliance 1/lambda'),
// so that W = mu'/2 C_D^2 + lambda'/2 C_H^2 up to a constant. With f = vec(F),
// g = vec(cof F), H_J = d^2 J/dF^2 (deformation_gradient.h):
//   P = mu' F + lambda' (J - alpha) cof F,
//   dP/dF = mu' I9 + lambda' g g^T + lambda' (J - alpha) H_J.
// Rest stability: P(I) = (mu' - lambda' (alpha - 1)) I = 0, what the shift alpha is for.
// Small-strain limit (worked out here and tested): with d(cof F)[H] = tr(H) I - H^T at
// F = I, dP[H] = mu' (H + H^T) + (lambda' - mu') tr(H) I; so the Lame parameters of
// the given (E, nu) map to mu' = mu, lambda' = lambda + mu (the mapping Macklin and
// Mueller take from Smith, de Goes and Kim 2018, section 3.4, for this energy).
//
// Polynomial in F: finite for every F, inverted and flat elements included.
#pragma once

#include <Eigen/Core>

#include "deformation_gradient.h"
#include "lame_parameters.h"

namespace tb {

/// The XPBD neo-Hookean law in its own parameters mu', lambda', alpha.
struct XpbdNeoHookean {
  double lambda = 0;  ///< lambda' = lambda + mu, Pa (the hydrostatic constraint's stiffness)
  double mu = 0;      ///< mu' = mu, Pa (the deviatoric constraint's stiffness)
  double alpha = 1;   ///< 1 + mu'/lambda'

  explicit XpbdNeoHookean(const LameParameters& lame)
      : lambda(lame.lambda + lame.mu), mu(lame.mu), alpha(1 + lame.mu / (lame.lambda + lame.mu)) {}

  /// W(F), J/m^3 per reference volume, finite for every finite F (3x3).
  double energy(const Eigen::Matrix3d& F) const {
    const double J = F.determinant();
    return 0.5 * mu * (F.squaredNorm() - 3) + 0.5 * lambda * (J - alpha) * (J - alpha);
  }

  /// P(F) (3x3, Pa), finite for every finite F.
  Eigen::Matrix3d first_piola(const Eigen::Matrix3d& F) const {
    return mu * F + (lambda * (F.determinant() - alpha)) * cofactor(F);
  }

  /// dP/dF (9x9, Pa; deformation_gradient.h's index convention).
  Matrix9d tangent(const Eigen::Matrix3d& F) const {
    const Vector9d g = flatten(cofactor(F));
    Matrix9d T = lambda * (g * g.transpose());
    T += (lambda * (F.determinant() - alpha)) * determinant_hessian(F);
    T.diagonal().array() += mu;
    return T;
  }

  /// The tangent contracted with one node's shape gradient (node_stiffness in
  /// deformation_gradient.h): H_J drops out, mu' |g|^2 I + lambda' (cof F g)(cof F g)^T.
  Eigen::Matrix3d node_stiffness(const Eigen::Matrix3d& F, const Eigen::Vector3d& g) const {
    const Eigen::Vector3d c = cofactor(F) * g;
    return mu * g.squaredNorm() * Eigen::Matrix3d::Identity() + lambda * (c * c.transpose());
  }
};

}  // namespace tb
