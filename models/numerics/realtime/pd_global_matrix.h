// The global matrix of Projective Dynamics (Bouaziz, Martin, Liu, Kavan and Pauly
// 2014) on P1 tets with a lumped mass, restricted to the free dofs:
//   A = M / h^2 + K_s + sum_t w V_t G_t^T G_t,
// G_t the tet's deformation-gradient operator (tet_element.h), K_s the body's
// springs (a compliant grasp's pads), diagonal like the mass. Since G_t^T G_t acts
// on the three coordinates alike, A = (M/h^2 + L_w) (x) I_3, L_w the scalar Laplacian
// of the tets with entries w V_t g_a . g_b; a held component removes its row and
// column, so A is three decoupled n-by-n systems, coordinate c restricted to the
// nodes free in c. Each distinct set of free nodes is factorised once (CHOLMOD,
// supernodal_cholesky.h); coordinates with the same set share the factor.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "mesh_types.h"
#include "supernodal_cholesky.h"
#include "tet_element.h"

namespace tb {

class PdGlobalMatrix {
 public:
  /// T: #T by 4; shapes: each tet's (tet_shape); node_weight: per node, m / h^2 plus
  /// its springs' stiffness, N/m (the lumped mass over the squared time step h);
  /// free: 3 by #V, 1 where a component moves; weight: w per unit volume, Pa.
  PdGlobalMatrix(const Tetrahedra& T, const std::vector<TetShape>& shapes, const Eigen::VectorXd& node_weight,
                 const Eigen::Matrix3Xd& free, double weight);
  ~PdGlobalMatrix();

  /// z = A^-1 q over the free components (q, z: 3 by #V; z is zero where held and q
  /// is not read there). No heap allocation.
  void solve(const Eigen::Matrix3Xd& q, Eigen::Matrix3Xd& z);

  /// Constraints that each act on one node along a direction (row a of N is
  /// directions[a]^T at node nodes[a]; a direction must be zero in the node's held
  /// components): schur = N A^-1 N^T (m by m) from the columns A_c^-1 e_v of the
  /// nodes v. A acts on the coordinates alike, so a node needs one scalar column per
  /// distinct factor, not three vector solves; A does not change, so a node's column
  /// is kept from call to call, and only the nodes new to the set are solved, all at
  /// once by a multi-right-hand-side solve (a contact set is mostly the last
  /// iteration's and the last frame's). No heap allocation once the storage has grown
  /// to the set's size and schur has its size (and OpenBLAS runs on one thread, as
  /// the runner sets it: its threaded dtrsm and dgemm allocate).
  void node_constraints(const std::vector<int>& nodes, const std::vector<Eigen::Vector3d>& directions,
                        Eigen::MatrixXd& schur);
  /// z += A^-1 N^T mu for the constraints of the last node_constraints call.
  void add_constraint_response(const Eigen::VectorXd& mu, Eigen::Matrix3Xd& z);

  /// Distinct factorisations (1 to 3) and their nonzeros, summed.
  int factors() const { return static_cast<int>(blocks_.size()); }
  double factor_nonzeros() const;

 private:
  struct Block {
    std::vector<int> nodes;  ///< the free nodes of its coordinates, increasing (row k: nodes[k])
    std::unique_ptr<SupernodalCholesky> cholesky;
    std::vector<int> row_of;  ///< per node, its row (-1: not free here)
    Eigen::VectorXd b, x;
    // node_constraints' kept columns: slot s holds A^-1 e_row(slot_node[s]) at
    // columns[s * rows, (s + 1) * rows), last needed by call used_in[s]; slot_of: per
    // node, its slot (-1 none, -2 queued for this call's solve). Grown, never shrunk.
    std::vector<int> slot_of, slot_node, missing;
    std::vector<long> used_in;
    std::vector<double> columns, units, solved;  ///< kept columns; this call's right-hand sides and answers
    SupernodalCholesky::BlockWorkspace workspace;
  };
  /// Puts the columns of `nodes` (those free in the block) into its slots, solving
  /// the ones it does not hold.
  void cache_columns(Block& block, const std::vector<int>& nodes);

  std::vector<int> constraint_nodes_;
  std::vector<Eigen::Vector3d> constraint_directions_;
  long call_ = 0;  ///< node_constraints calls so far
  std::vector<Block> blocks_;
  int block_of_[3] = {-1, -1, -1};  ///< per coordinate, its block (-1: no free node)
};

}  // namespace tb
