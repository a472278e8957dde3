// A linear-elastic body on a tet mesh with clamped nodes: K u = f (eq. 11) solved
// once per frame, either by back-substitution with a factorisation made in the
// constructor (direct) or by warm-started preconditioned CG (iterative). The same
// class solves the fine reference mesh and the hybrid's coarse mesh.
#pragma once

#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

#include "mesh_types.h"
#include "model.h"

namespace tb {

enum class SolveMode { Direct, Iterative };

/// Limits OpenBLAS (under CHOLMOD), OpenMP and deal.II's task pool (TBB, used when
/// a Triangulation is built) to one thread, so that every timing the project
/// reports is single-threaded. Call once at program start.
void use_one_thread();

/// The four nodes and barycentric weights over which a point force is spread
/// (eq. 10 for a point force: f^e = N^e(x)^T F).
struct LoadStencil {
  Eigen::Vector4i nodes = Eigen::Vector4i::Zero();
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();
};

class ElasticSolver {
 public:
  /// Assembles K, removes the clamped dofs and factorises (direct) or builds the
  /// preconditioner (iterative).
  ///   clamped  #V flags, 1 = zero displacement
  /// Throws std::invalid_argument if nothing is clamped (K is singular).
  ///   coarse_space  iterative mode only: a coarser tet mesh of the same body whose
  ///                 P1 interpolation is the coarse space of a two-level
  ///                 preconditioner (nullptr: incomplete Cholesky alone)
  ElasticSolver(const TetMesh& mesh, const Material& material, const std::vector<char>& clamped, SolveMode mode,
                double cg_relative_tolerance = 1e-8, const TetMesh* coarse_space = nullptr);
  ~ElasticSolver();
  ElasticSolver(const ElasticSolver&) = delete;
  ElasticSolver& operator=(const ElasticSolver&) = delete;

  /// The tet containing `point` and its weights; throws std::invalid_argument naming
  /// the point if it is outside the mesh (beyond a 1e-6 relative tolerance).
  LoadStencil locate_load(const Eigen::Vector3d& point) const;

  /// Solves for the displacement under `force` applied through `stencil`.
  ///   u  3 #V displacements (dof 3 * node + component); also the warm start
  void solve(const LoadStencil& stencil, const Eigen::Vector3d& force, Eigen::VectorXd& u);

  /// The full (unconstrained) 3 #V by 3 #V stiffness matrix, e.g. for reactions.
  const Eigen::SparseMatrix<double>& full_stiffness() const { return K_full_; }
  int last_iterations() const { return last_iterations_; }
  /// Nonzeros of the Cholesky factor (direct mode; 0 otherwise): its memory is
  /// 8 bytes each plus indices, the bulk of the solver's.
  double factor_nonzeros() const;
  int free_dofs() const { return static_cast<int>(free_to_full_.size()); }
  const TetMesh& mesh() const { return mesh_; }

 private:
  struct Factorisation;
  TetMesh mesh_;
  SolveMode mode_;
  Eigen::SparseMatrix<double> K_full_;
  std::vector<int> full_to_free_;  ///< -1 for clamped dofs
  std::vector<int> free_to_full_;
  std::unique_ptr<Factorisation> fact_;
  Eigen::VectorXd f_free_, u_free_;  ///< work vectors, allocated once
  int last_iterations_ = 0;
};

}  // namespace tb
