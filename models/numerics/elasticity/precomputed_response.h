// Precomputed elementary responses of a linear-elastic body (Cotin, Delingette and
// Ayache 1999; the condensation of Bro-Nielsen and Cotin 1996): the displacement of
// chosen output nodes under a unit force in x, y and z at a loaded node, from the
// factor made once (the columns of 32 nodes solved together: one forward and one
// backward substitution of 96 right-hand sides, SupernodalCholesky's matrix solve). Linear elasticity
// superposes, so any point load is then a weighted sum of columns: exact, and a
// few thousand multiply-adds per frame. A load spread over many nodes (a disc
// traction, gravity) gets three columns of its own instead: the outputs'
// response to its nodal weights times a unit value in x, y and z.
//
// Prescribed displacements (a grasp, a plate: the body's PrescribedGroups) are
// Dirichlet values, so they superpose too: each group gets three columns of its
// own, the outputs' response to a unit translation of its held components
// (K_ff u_f = -K_fp e, one back-substitution each; the factor is of K_ff, the
// held dofs removed, so it is made once for the tool set). Every column also
// carries the reactions it causes on each group and on the support (f - K u at the
// constrained dofs, ElasticBody::reactions), so a frame's reaction forces are
// superposed from 3 x (#groups + 1) numbers per column as well.
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

  /// `body` must outlive this. Factorises K_ff (a direct elastic solve) and
  /// computes the columns of the body's prescribed groups.
  ///   outputs  #O volume nodes whose displacement is wanted, in output order
  PrecomputedResponse(const ElasticBody& body, std::vector<int> outputs);

  /// Computes the three columns of each node not yet computed (a force on a
  /// clamped or held dof moves nothing and goes to the support or the group).
  void precompute(const std::vector<int>& loaded_nodes);

  /// Computes what apply() needs for `loads` (which must outlive this): the node
  /// columns of its narrow loads, the own columns of its wide ones. A set-up call.
  void prepare(const BodyLoads& loads);

  /// out (#O by 3): the outputs' displacement under `loads` with `values` (one per
  /// load) and the prescribed groups at `group_values` (one per group of the body);
  /// `reactions` (if not null; resized to #groups + 1): the force the body exerts on
  /// each group and then on the support, N. `loads` must be the prepared ones (else
  /// std::logic_error). No allocation once the outputs have their sizes.
  void apply(const BodyLoads& loads, const std::vector<Eigen::Vector3d>& values,
             const std::vector<Eigen::Vector3d>& group_values, Points& out,
             std::vector<Eigen::Vector3d>* reactions = nullptr) const;
  /// apply() for a body with no prescribed group, without reactions.
  void apply(const BodyLoads& loads, const std::vector<Eigen::Vector3d>& values, Points& out) const {
    apply(loads, values, {}, out);
  }

  int nodes_computed() const { return static_cast<int>(columns_.size()); }
  /// Bytes held by the columns: per loaded node, per wide load and per group,
  /// 9 #O doubles of outputs and 9 (#groups + 1) of reactions.
  double memory_bytes() const;

 private:
  /// Three responses side by side: row o = (value o under e_x, under e_y, under e_z).
  using Columns = Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor>;
  /// One source's responses: of the outputs (#O rows) and of the reactions
  /// (#groups + 1 rows: each group's force, then the support's).
  struct Response {
    Columns outputs, reactions;
  };
  const ElasticBody& body_;
  std::vector<int> outputs_;
  std::unique_ptr<ElasticSolve> direct_;
  std::vector<int> slot_;            ///< per volume node: index into columns_, -1 if none
  std::vector<Response> columns_;    ///< per loaded node: the response to a unit force along x, y, z
  std::vector<Response> groups_;     ///< per prescribed group: the response to a unit translation
  const BodyLoads* prepared_ = nullptr;
  std::vector<Response> load_columns_;  ///< per prepared load: its own columns (empty for a narrow load)
  Eigen::VectorXd u_, f_, f_full_;      ///< work vectors of a column solve
  mutable std::vector<Eigen::Vector3d> group_work_;  ///< ElasticBody::reactions' output for one column
  Response zero_response() const;
  /// Column c of `into`: the outputs' rows of u_ and the reactions of (u_, f_full_).
  void store(Response& into, int c) const;
};

}  // namespace tb
