// Precomputed elementary responses of a linear-elastic body (Cotin, Delingette and
// Ayache 1999; the condensation of Bro-Nielsen and Cotin 1996): the displacement of
// chosen output nodes under a unit force in x, y and z at a loaded node, one
// back-substitution of the factor made once per column. Linear elasticity
// superposes, so any point load is then a weighted sum of columns: exact, and a
// few thousand multiply-adds per frame. A load spread over many nodes (a disc
// traction, gravity) gets three columns of its own instead: the outputs'
// response to its nodal weights times a unit value in x, y and z.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "elastic_body.h"
#include "elastic_solve.h"

namespace tb {

class PrecomputedResponse {
 public:
  /// A load on at most this many nodes is superposed from node columns; a wider
  /// one gets its own three columns.
  static constexpr Eigen::Index kNodeColumnsUpTo = 4;

  /// `body` must outlive this. Factorises K (a direct elastic solve).
  ///   outputs  #O volume nodes whose displacement is wanted, in output order
  PrecomputedResponse(const ElasticBody& body, std::vector<int> outputs);

  /// Computes the three columns of each node not yet computed (clamped nodes
  /// need none: a force there goes to the support).
  void precompute(const std::vector<int>& loaded_nodes);

  /// Computes what apply() needs for `loads` (which must outlive this): the node
  /// columns of its narrow loads, the own columns of its wide ones. A set-up call.
  void prepare(const BodyLoads& loads);

  /// out (#O by 3): the outputs' displacement under `loads` with `values` (one per
  /// load). `loads` must be the prepared ones (else std::logic_error). No allocation.
  void apply(const BodyLoads& loads, const std::vector<Eigen::Vector3d>& values, Points& out) const;

  int nodes_computed() const { return static_cast<int>(columns_.size()); }
  /// Bytes held by the columns: 9 #O doubles per loaded node and per wide load.
  double memory_bytes() const;

 private:
  using Columns = Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor>;
  const ElasticBody& body_;
  std::vector<int> outputs_;
  std::unique_ptr<ElasticSolve> direct_;
  std::vector<int> slot_;  ///< per volume node: index into columns_, -1 if none
  /// per loaded node: #O by 3 blocks for a unit force in x, y, z, side by side
  /// (#O by 9, row o = (u_o under e_x, u_o under e_y, u_o under e_z))
  std::vector<Columns> columns_;
  const BodyLoads* prepared_ = nullptr;
  std::vector<Columns> load_columns_;  ///< per prepared load: its own columns (empty for a narrow load)
  Eigen::VectorXd u_, f_;              ///< work vectors of a column solve
  /// The outputs' rows of u (#O by 9 block `c` of `into`).
  void store_outputs(Columns& into, int c) const;
};

}  // namespace tb
