// Unilateral frictionless contact of a linear-elastic body with rigid spheres, by an
// active set of Lagrange multipliers on the factorised K (docs/equations.md,
// "Contact with a rigid sphere"). Each surface node i in contact with sphere k has
// the linearised, normal-only constraint n_i . u_i = n_i . (c_k + r_k n_i - X_i),
// n_i the outward normal at the point of the sphere nearest the node's current
// position; its multiplier lambda_i >= 0 is the normal contact force.
//
// Why multipliers on the existing factorisation, not Dirichlet values: a sphere's
// normal differs from node to node, while ElasticBody prescribes whole components
// along x, y, z, fixed when K_ff is factorised; rotating each contact node's dofs
// to its normal (or a penalty k n n^T) would change K_ff and refactorise it at every
// change of the active set. With the multipliers (Wriggers 2006, "Computational
// Contact Mechanics", ch. 6: Lagrange multiplier method and active set strategy)
// K_ff is factorised once: the flexibility G = K_ff^{-1} restricted to the
// candidate nodes (3 solves per candidate node) gives the Schur complement
// S = N G N^T, and each active-set iteration is a small dense solve S lambda = g.
// The active set: nodes whose position penetrates a sphere join; nodes whose
// multiplier is tensile (lambda < 0: the tissue pulls away) leave; the normals are
// re-linearised at the new positions; until the set does not change and every
// active node lies on its sphere within 1e-6 r (Hueeber and Wohlmuth 2005 call this a
// primal-dual active set method).
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <vector>

#include "elastic_body.h"
#include "elastic_solve.h"

namespace tb {

class SphereContact {
 public:
  static constexpr int kMaxIterations = 100;  ///< active-set iterations per frame before it is an error

  /// `body` and `solve` (a linear strategy) must outlive this.
  ///   surface_nodes  the body's node of each surface vertex (the candidates)
  SphereContact(const ElasticBody& body, ElasticSolve& solve, std::vector<int> surface_nodes);

  /// Which surface nodes get a flexibility column (3 solves each, the cost of a
  /// frame whose candidates change): those free nodes nearer a sphere's centre, at
  /// the solution without contact, than r + margin r + depth_factor times the
  /// deepest penetration. A node found inside the sphere that is not a candidate
  /// joins and G is rebuilt, so these change the cost, not the solution (unless a
  /// node is still missed after 3 rebuilds: then penetration() reports it).
  void set_candidate_margin(double margin, double depth_factor) {
    margin_ = margin;
    depth_factor_ = depth_factor;
  }

  /// u (3 #V) in: the body's solution without contact under this frame's loads and
  /// prescribed values; out: with the spheres (centres #S by 3, radii #S).
  /// Throws std::runtime_error when the active set does not settle in
  /// kMaxIterations.
  void solve(const Eigen::MatrixX3d& centres, const Eigen::VectorXd& radii, Eigen::VectorXd& u);

  /// After solve(): per sphere, the force the body exerts on it (N), the surface
  /// vertices in contact (ascending) and the deepest surface vertex inside it (m).
  const std::vector<Eigen::Vector3d>& forces() const { return force_; }
  const std::vector<std::vector<int>>& contact_vertices() const { return contact_; }
  const std::vector<double>& penetration() const { return depth_; }
  /// After solve(): the contact force on the body at each active node, (node, N);
  /// an external force for the reactions of the support and the other tools.
  const std::vector<std::pair<int, Eigen::Vector3d>>& node_forces() const { return node_forces_; }
  /// Facts for run.json: iterations and candidates of the last frame, the largest over the frames.
  nlohmann::json report() const;
  int last_iterations() const { return iterations_; }

 private:
  const ElasticBody& body_;
  ElasticSolve& solve_;
  std::vector<int> surface_nodes_;
  std::vector<int> candidates_;  ///< surface vertices whose flexibility G holds, ascending
  Eigen::MatrixXd G_;            ///< K_ff^{-1} on the candidates' dofs (3 per candidate)
  std::vector<std::pair<int, int>> active_;  ///< (candidate index, sphere) in contact, from the last frame
  std::vector<Eigen::Vector3d> force_;
  std::vector<std::vector<int>> contact_;
  std::vector<double> depth_;
  std::vector<std::pair<int, Eigen::Vector3d>> node_forces_;
  Eigen::VectorXd f_free_, w_, column_;
  double margin_ = 0.1, depth_factor_ = 2;
  int iterations_ = 0, max_iterations_seen_ = 0, candidate_count_max_ = 0;
  int flexibility_solves_ = 0;  ///< unit-force columns of G computed (solved together in blocks when factorised)
  /// G for the candidate list (3 solves per candidate).
  void build_flexibility();
};

}  // namespace tb
