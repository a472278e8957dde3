// Compressible neo-Hookean solid (Bonet and Wood 2008, eq. 6.28), the law the
// distributed large-deformation reference used first (fem_distributed/):
//   W(F) = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2,   I1 = tr(F^T F), J = det F,
//   P(F) = mu F + (lambda ln J - mu) F^-T
//        = mu F + (lambda ln J - mu) / J cof F                 (cof F = dJ/dF = J F^-T),
//   dP/dF = mu I9 + (lambda (1 - ln J) + mu) / J^2 g g^T + (lambda ln J - mu) / J H_J,
// with g = vec(cof F) and H_J = d^2 J/dF^2 (deformation_gradient.h). This is the
// tangent the distributed solver wrote by hand before it used this law, as
//   dP[dF] = mu dF + (mu - lambda ln J) F^-T dF^T F^-T + lambda (F^-T : dF) F^-T.
// At F = I: P = 0 and dP[H] = mu (H + H^T) + lambda tr(H) I, linear elasticity
// with the same lambda and mu.
//
// Undefined for J <= 0 (ln J): energy() returns +infinity there, so that a line
// search or an energy-based step rejects an inverted state; first_piola() and
// tangent() throw std::domain_error (deformation_gradient.h's throw_inverted),
// never a NaN. A NaN in F counts as J <= 0.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "deformation_gradient.h"
#include "lame_parameters.h"
#include "lane_math.h"
#include "node_terms.h"

namespace tb {

/// The coupled compressible neo-Hookean law; its parameters are the Lame parameters.
struct NeoHookean {
  double lambda = 0;  ///< Pa
  double mu = 0;      ///< Pa

  explicit NeoHookean(const LameParameters& lame) : lambda(lame.lambda), mu(lame.mu) {}

  /// W(F), J/m^3 per reference volume; +infinity if det F <= 0. F: 3x3.
  double energy(const Eigen::Matrix3d& F) const {
    const double J = F.determinant();
    if (!(J > 0)) return std::numeric_limits<double>::infinity();
    const double ln_J = std::log(J);
    return 0.5 * mu * (F.squaredNorm() - 3) - mu * ln_J + 0.5 * lambda * ln_J * ln_J;
  }

  /// P(F) (3x3, Pa). Throws std::domain_error if det F <= 0.
  Eigen::Matrix3d first_piola(const Eigen::Matrix3d& F) const {
    const double J = F.determinant();
    if (!(J > 0)) throw_inverted("neo_hookean", "first Piola-Kirchhoff stress", J);
    return mu * F + ((lambda * std::log(J) - mu) / J) * cofactor(F);
  }

  /// dP/dF (9x9, Pa; deformation_gradient.h's index convention). Throws
  /// std::domain_error if det F <= 0.
  Matrix9d tangent(const Eigen::Matrix3d& F) const {
    const double J = F.determinant();
    if (!(J > 0)) throw_inverted("neo_hookean", "tangent", J);
    const double ln_J = std::log(J);
    const Vector9d g = flatten(cofactor(F));
    Matrix9d T = ((lambda * (1 - ln_J) + mu) / (J * J)) * (g * g.transpose());
    T += ((lambda * ln_J - mu) / J) * determinant_hessian(F);
    T.diagonal().array() += mu;
    return T;
  }

  /// The tangent contracted with one node's shape gradient g (contract_tangent in
  /// deformation_gradient.h; H_J drops out): mu |g|^2 I + (lambda (1 - ln J) + mu) / J^2
  /// (cof F g)(cof F g)^T. Throws std::domain_error if det F <= 0.
  Eigen::Matrix3d node_stiffness(const Eigen::Matrix3d& F, const Eigen::Vector3d& g) const {
    const double J = F.determinant();
    if (!(J > 0)) throw_inverted("neo_hookean", "node stiffness", J);
    const Eigen::Vector3d c = cofactor(F) * g;
    return mu * g.squaredNorm() * Eigen::Matrix3d::Identity() +
           ((lambda * (1 - std::log(J)) + mu) / (J * J)) * (c * c.transpose());
  }

  /// P(F) g, node_stiffness(F, g), cof(F) g and J together (node_terms.h), with J,
  /// ln J, 1/J and c = cof(F) g computed once: P g = mu F g + (lambda ln J - mu) / J c,
  /// J = f0 . (f1 x f2) (f0 and the first column of cof F). Equal to the separate
  /// functions to round-off. Inlined (the sweep's inner loop: as a call, its result
  /// went through memory). Throws std::domain_error if det F <= 0.
  [[gnu::always_inline]] NodeTerms node_terms(const Eigen::Matrix3d& F, const Eigen::Vector3d& g) const {
    const Eigen::Matrix3d C = cofactor(F);
    const double J = F.col(0).dot(C.col(0));
    if (!(J > 0)) throw_inverted("neo_hookean", "node terms", J);
    const double ln_J = std::log(J), inv_J = 1 / J;
    NodeTerms r;
    r.cof_g = C * g;
    r.force = mu * (F * g) + ((lambda * ln_J - mu) * inv_J) * r.cof_g;
    r.stiffness = ((lambda * (1 - ln_J) + mu) * inv_J * inv_J) * (r.cof_g * r.cof_g.transpose());
    r.stiffness.diagonal().array() += mu * g.squaredNorm();
    r.J = J;
    return r;
  }

  /// node_terms on a batch of tets, one per lane (T: a lanes vector of doubles,
  /// pbd/lane_math.h; Vertex Block Descent's batched sweep, vbd_visit_blocks.h), from F,
  /// its cofactor C (both [row][column]) and J = det F, which the caller has checked
  /// positive in every lane: force = P(F) g, c = cof(F) g, and the node stiffness as
  /// s_cc c c^T + s_I I (s_I = mu |g|^2). The formulas of node_terms; ln J by
  /// lanes::log (within 1 ulp of std::log).
  template <class T>
  [[gnu::always_inline]] void lane_node_terms(const T (&F)[3][3], const T (&C)[3][3], const T& J, const T (&g)[3],
                                              T (&force)[3], T (&c)[3], T& s_cc, T& s_I) const {
    namespace L = pbd::lanes;
    const T ln_J = L::log(J), inv_J = L::splat<T>(1) / J, mu_ = L::splat<T>(mu), lambda_ = L::splat<T>(lambda);
    const T a = (lambda_ * ln_J - mu_) * inv_J;
    for (int i = 0; i < 3; ++i) {
      c[i] = C[i][0] * g[0] + C[i][1] * g[1] + C[i][2] * g[2];
      force[i] = mu_ * (F[i][0] * g[0] + F[i][1] * g[1] + F[i][2] * g[2]) + a * c[i];
    }
    s_cc = (lambda_ * (L::splat<T>(1) - ln_J) + mu_) * inv_J * inv_J;
    s_I = mu_ * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  }
};

}  // namespace tb
