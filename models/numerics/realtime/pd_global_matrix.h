// The global matrix of Projective Dynamics (Bouaziz, Martin, Liu, Kavan and Pauly
// 2014) on P1 tets with a lumped mass, restricted to the free dofs:
//   A = M / h^2 + sum_t w V_t G_t^T G_t,
// G_t the tet's deformation-gradient operator (tet_element.h). Since G_t^T G_t acts
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
  /// T: #T by 4; shapes: each tet's (tet_shape); mass: lumped, per node; free: 3 by #V,
  /// 1 where a component moves; h: the time step, s; weight: w per unit volume, Pa.
  PdGlobalMatrix(const Tetrahedra& T, const std::vector<TetShape>& shapes, const Eigen::VectorXd& mass,
                 const Eigen::Matrix3Xd& free, double h, double weight);
  ~PdGlobalMatrix();

  /// z = A^-1 q over the free components (q, z: 3 by #V; z is zero where held and q
  /// is not read there). No heap allocation.
  void solve(const Eigen::Matrix3Xd& q, Eigen::Matrix3Xd& z);

  /// Distinct factorisations (1 to 3) and their nonzeros, summed.
  int factors() const { return static_cast<int>(blocks_.size()); }
  double factor_nonzeros() const;

 private:
  struct Block {
    std::vector<int> nodes;  ///< the free nodes of its coordinates, increasing (row k: nodes[k])
    std::unique_ptr<SupernodalCholesky> cholesky;
    Eigen::VectorXd b, x;
  };
  std::vector<Block> blocks_;
  int block_of_[3] = {-1, -1, -1};  ///< per coordinate, its block (-1: no free node)
};

}  // namespace tb
