// Neo-Hookean solid with the isochoric/volumetric split (Flory 1961), in the form
// Abaqus-style codes document their neo-Hookean potential:
//   W(F) = C10 (I1bar - 3) + (J - 1)^2 / D1,   I1bar = J^(-2/3) I1, I1 = tr(F^T F),
// with C10 = mu/2 and D1 = 2/K (K = lambda + 2 mu/3), so that the initial shear
// modulus 2 C10 and bulk modulus 2/D1 are those of the given (E, nu). Writing
// c = C10, k = 2/D1 = K, a = J^(-2/3), s = a I1 / J, f = vec(F), g = vec(cof F):
//   P = 2 c a F - (2c/3) s cof F + k (J - 1) cof F,
//   dP/dF = 2 c a I9 - (4c/3)(a/J)(f g^T + g f^T) + ((10c/9) s/J + k) g g^T
//           + (k (J - 1) - (2c/3) s) H_J                     (H_J: deformation_gradient.h).
// At F = I: P = 0 and dP[H] = mu (H + H^T) + (K - 2 mu/3) tr(H) I, linear elasticity.
// Under large volume change it differs from the coupled law (neo_hookean.h):
// its volumetric term stays finite as J -> 0.
//
// Undefined for J <= 0 (I1bar is the shape of a positive volume; J^(-2/3) is
// unbounded at J = 0): energy() returns +infinity there, first_piola() and
// tangent() throw std::domain_error, as neo_hookean.h does.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "deformation_gradient.h"
#include "lame_parameters.h"

namespace tb {

/// The isochoric/volumetric neo-Hookean law, in its own parameters C10 and D1.
struct NeoHookeanIsochoric {
  double c10 = 0;  ///< C10 = mu / 2, Pa
  double d1 = 0;   ///< D1 = 2 / K, 1/Pa

  explicit NeoHookeanIsochoric(const LameParameters& lame) : c10(lame.mu / 2), d1(2 / lame.bulk_modulus()) {}

  /// W(F), J/m^3 per reference volume; +infinity if det F <= 0. F: 3x3.
  double energy(const Eigen::Matrix3d& F) const {
    const double J = F.determinant();
    if (!(J > 0)) return std::numeric_limits<double>::infinity();
    return c10 * (std::pow(J, -2.0 / 3.0) * F.squaredNorm() - 3) + (J - 1) * (J - 1) / d1;
  }

  /// P(F) (3x3, Pa). Throws std::domain_error if det F <= 0.
  Eigen::Matrix3d first_piola(const Eigen::Matrix3d& F) const {
    const double J = F.determinant();
    if (!(J > 0)) throw_inverted("neo_hookean_isochoric", "first Piola-Kirchhoff stress", J);
    const double a = std::pow(J, -2.0 / 3.0), s = a * F.squaredNorm() / J, k = 2 / d1;
    return (2 * c10 * a) * F + (k * (J - 1) - (2 * c10 / 3) * s) * cofactor(F);
  }

  /// dP/dF (9x9, Pa; deformation_gradient.h's index convention). Throws
  /// std::domain_error if det F <= 0.
  Matrix9d tangent(const Eigen::Matrix3d& F) const {
    const double J = F.determinant();
    if (!(J > 0)) throw_inverted("neo_hookean_isochoric", "tangent", J);
    const double a = std::pow(J, -2.0 / 3.0), s = a * F.squaredNorm() / J, k = 2 / d1;
    const Vector9d f = flatten(F), g = flatten(cofactor(F));
    const Matrix9d fg = f * g.transpose();
    Matrix9d T = (-(4 * c10 / 3) * a / J) * (fg + fg.transpose());
    T += ((10 * c10 / 9) * s / J + k) * (g * g.transpose());
    T += (k * (J - 1) - (2 * c10 / 3) * s) * determinant_hessian(F);
    T.diagonal().array() += 2 * c10 * a;
    return T;
  }

  /// The tangent contracted with one node's shape gradient g (deformation_gradient.h's
  /// contract_tangent; no closed form written). Throws std::domain_error if det F <= 0.
  Eigen::Matrix3d node_stiffness(const Eigen::Matrix3d& F, const Eigen::Vector3d& g) const {
    return contract_tangent(tangent(F), g);
  }
};

}  // namespace tb
