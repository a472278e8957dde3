// One node's share of a P1 tet's force and stiffness, the per-tet terms of a
// per-vertex Newton step (Vertex Block Descent, Chen et al. 2024, eqs. 7-8): with g
// the node's shape gradient,
//   force     = P(F) g                     (the node's internal force per unit volume),
//   stiffness = dP/dF contracted with (g, g) (node_stiffness; contract_tangent),
//   cof_g     = cof(F) g, and J = det F     (moving the node by dx makes det F exactly
//                                            J + dx . cof_g: F changes by dx g^T, rank one).
// node_terms(law, F, g) is the law's own node_terms(F, g) where it has one (a closed
// form sharing J, cof F and ln J among the four; neo_hookean.h), else the law's
// first_piola and node_stiffness, each of which recomputes what it needs.
#pragma once

#include <Eigen/Core>
#include <type_traits>
#include <utility>

#include "deformation_gradient.h"

namespace tb {

/// force (Pa/m), stiffness (Pa/m^2), cof_g (1/m) and J (F is dimensionless).
struct NodeTerms {
  Eigen::Vector3d force;
  Eigen::Matrix3d stiffness;
  Eigen::Vector3d cof_g;
  double J = 0;
};

template <class Law, class = void>
struct HasNodeTerms : std::false_type {};
template <class Law>
struct HasNodeTerms<Law, std::void_t<decltype(std::declval<const Law&>().node_terms(
                             std::declval<const Eigen::Matrix3d&>(), std::declval<const Eigen::Vector3d&>()))>>
    : std::true_type {};

/// The node terms of `law` at F for shape gradient g (header comment). Throws what
/// the law throws (std::domain_error at det F <= 0 for a law undefined there).
/// Inlined: called in the sweep's inner loop, where as a call its result went through memory.
template <class Law>
[[gnu::always_inline]] inline NodeTerms node_terms(const Law& law, const Eigen::Matrix3d& F, const Eigen::Vector3d& g) {
  if constexpr (HasNodeTerms<Law>::value) {
    return law.node_terms(F, g);
  } else {
    return {law.first_piola(F) * g, law.node_stiffness(F, g), cofactor(F) * g, F.determinant()};
  }
}

}  // namespace tb
