// Precomputed elementary responses of a linear-elastic body (Cotin, Delingette and
// Ayache 1999; the condensation of Bro-Nielsen and Cotin 1996): the displacement of
// chosen output nodes under a unit force in x, y and z at a loaded node, one
// back-substitution of the factor made once per column. Linear elasticity
// superposes, so any point load is then a weighted sum of columns: exact, and a
// few thousand multiply-adds per frame.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "load_mapping.h"

namespace tb {

class PrecomputedResponse {
 public:
  /// `body` must outlive this. Factorises K (a "direct" elastic solve).
  ///   outputs  #O volume nodes whose displacement is wanted, in output order
  PrecomputedResponse(const ElasticBody& body, std::vector<int> outputs);

  /// Computes the three columns of each node not yet computed (clamped nodes
  /// need none: a force there goes to the support).
  void precompute(const std::vector<int>& loaded_nodes);

  /// out (#O by 3): the outputs' displacement under `force` spread by `load`.
  /// Columns missing for the load's nodes are computed first (that allocates; a
  /// fixed load point allocates on its first frame only).
  void apply(const LoadStencil& load, const Eigen::Vector3d& force, Points& out);

  int nodes_computed() const { return static_cast<int>(columns_.size()); }
  /// Bytes held by the columns: 9 #O doubles per loaded node.
  double memory_bytes() const;

 private:
  const ElasticBody& body_;
  std::vector<int> outputs_;
  std::unique_ptr<ElasticSolve> direct_;
  std::vector<int> slot_;  ///< per volume node: index into columns_, -1 if none
  /// per loaded node: #O by 3 blocks for a unit force in x, y, z, side by side
  /// (#O by 9, row o = (u_o under e_x, u_o under e_y, u_o under e_z))
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor>> columns_;
  Eigen::VectorXd u_;  ///< work vector of a column solve
};

}  // namespace tb
