// Small-strain linear isotropic elasticity written as a function of the
// deformation gradient F, so that it has the interface of the finite-strain laws:
//   eps = sym(F - I) = sym(grad u),
//   W(F) = mu eps : eps + lambda/2 tr(eps)^2                       (J/m^3),
//   P(F) = dW/dF = sigma(eps) = 2 mu eps + lambda tr(eps) I        (Pa),
//   dP_ij/dF_kl = C_ijkl = lambda d_ij d_kl + mu (d_ik d_jl + d_il d_jk),
// the isotropic elasticity tensor acting on grad u, symmetrised in (k, l), and
// constant. It is the law of the serial stiffness K = sum_e int B^T D B: with a
// linear tet's constant shape gradients, tet_stiffness (tet_element.h) gives that
// B^T D B from this tangent.
//
// Not frame-indifferent: eps of a rigid rotation R is sym(R) - I != 0, so a
// rotated, unstrained element stores energy (the reason for corotational and
// finite-strain laws). Defined, finite and rest-stress-free (P(I) = 0) for every F.
#pragma once

#include <Eigen/Core>

#include "deformation_gradient.h"
#include "lame_parameters.h"

namespace tb {

/// Linear isotropic elasticity; its parameters are the Lame parameters themselves.
struct LinearElastic {
  double lambda = 0;  ///< Pa
  double mu = 0;      ///< Pa

  explicit LinearElastic(const LameParameters& lame) : lambda(lame.lambda), mu(lame.mu) {}

  /// W(F), J/m^3 per reference volume. F: 3x3.
  double energy(const Eigen::Matrix3d& F) const {
    const Eigen::Matrix3d eps = strain(F);
    const double tr = eps.trace();
    return mu * eps.squaredNorm() + 0.5 * lambda * tr * tr;
  }

  /// P(F) = sigma(eps) (3x3, Pa).
  Eigen::Matrix3d first_piola(const Eigen::Matrix3d& F) const {
    const Eigen::Matrix3d eps = strain(F);
    return 2 * mu * eps + lambda * eps.trace() * Eigen::Matrix3d::Identity();
  }

  /// dP/dF (9x9, Pa; deformation_gradient.h's index convention), the same for every F.
  Matrix9d tangent(const Eigen::Matrix3d& /*F*/) const {
    Matrix9d C = Matrix9d::Zero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        // d_ij d_kl: the trace couples the diagonal entries.
        if (i == j)
          for (int k = 0; k < 3; ++k) C(i + 3 * i, k + 3 * k) += lambda;
        // mu (d_ik d_jl + d_il d_jk): column (i, j) and column (j, i).
        C(i + 3 * j, i + 3 * j) += mu;
        C(i + 3 * j, j + 3 * i) += mu;
      }
    return C;
  }

  /// Entry (ci, cj) of the 3x3 block that two shape functions with gradients ga
  /// and gb (each 3, 1/m) give the element stiffness per unit volume:
  ///   sum_{j,l} C_{ci j cj l} ga_j gb_l = lambda ga_ci gb_cj + mu ga_cj gb_ci + [ci = cj] mu ga . gb
  /// (the isotropic B^T D B of paper eq. 9, as deal.II step-8 writes it). The one
  /// coding of it: the serial assembly (stiffness_assembly.cc) and the distributed
  /// solver's linear cells use this; tet_stiffness with tangent() gives the same to
  /// round-off (tests/models/numerics/materials/material_laws_test.cc). Vec: any
  /// type with operator[] (const double*, Eigen, deal.II tensors).
  template <class Vec>
  double stiffness_entry(const Vec& ga, const Vec& gb, int ci, int cj) const {
    double k = ga[ci] * gb[cj] * lambda + ga[cj] * gb[ci] * mu;
    if (ci == cj) k += (ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2]) * mu;
    return k;
  }

  /// The tangent contracted with one node's shape gradient g (contract_tangent in
  /// deformation_gradient.h): stiffness_entry(g, g, i, k), (lambda + mu) g g^T + mu |g|^2 I.
  Eigen::Matrix3d node_stiffness(const Eigen::Matrix3d& /*F*/, const Eigen::Vector3d& g) const {
    return (lambda + mu) * (g * g.transpose()) + mu * g.squaredNorm() * Eigen::Matrix3d::Identity();
  }

  /// eps = sym(F - I) (3x3).
  static Eigen::Matrix3d strain(const Eigen::Matrix3d& F) {
    return 0.5 * (F + F.transpose()) - Eigen::Matrix3d::Identity();
  }
};

}  // namespace tb
