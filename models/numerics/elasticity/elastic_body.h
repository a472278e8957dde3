// A linear-elastic body on a tet mesh with clamped nodes, assembled once: the
// stiffness K of eq. (11), which dofs are free, and K restricted to them
// (Dirichlet u = 0 on the clamped ones). What every way of solving K u = f
// shares (elastic_solve.h); the fine FEM and the hybrid's coarse mesh each hold one.
#pragma once

#include <Eigen/SparseCore>
#include <vector>

#include "load_mapping.h"
#include "material.h"
#include "mesh_types.h"

namespace tb {

/// Limits OpenBLAS (under CHOLMOD), OpenMP and deal.II's task pool (TBB, used when
/// a Triangulation is built) to one thread, so that every timing the project
/// reports is single-threaded. Call once at program start.
void use_one_thread();

class ElasticBody {
 public:
  /// Assembles K (deal.II, stiffness_assembly.h) and removes the clamped dofs.
  ///   clamped  #V flags, 1 = zero displacement
  /// Throws std::invalid_argument if nothing is clamped (K is singular) or
  /// everything is.
  ElasticBody(const TetMesh& mesh, const Material& material, const std::vector<char>& clamped);

  const TetMesh& mesh() const { return mesh_; }
  const Material& material() const { return material_; }
  /// The full (unconstrained) 3 #V by 3 #V stiffness; dof 3 * node + component.
  const Eigen::SparseMatrix<double>& full_stiffness() const { return K_full_; }
  /// K on the free dofs only (both triangles stored).
  const Eigen::SparseMatrix<double>& free_stiffness() const { return K_free_; }
  int dofs() const { return static_cast<int>(full_to_free_.size()); }
  int free_dofs() const { return static_cast<int>(free_to_full_.size()); }
  /// The free index of a full dof, -1 when clamped.
  int free_index(int dof) const { return full_to_free_[static_cast<size_t>(dof)]; }

  /// u (3 #V) -> u_free, and back (clamped dofs set to 0). No allocation when the
  /// output already has its size.
  void to_free(const Eigen::VectorXd& u, Eigen::VectorXd& u_free) const;
  void to_full(const Eigen::VectorXd& u_free, Eigen::VectorXd& u) const;

 private:
  TetMesh mesh_;
  Material material_;
  Eigen::SparseMatrix<double> K_full_, K_free_;
  std::vector<int> full_to_free_;  ///< -1 for clamped dofs
  std::vector<int> free_to_full_;
};

/// The loads of a run on one body, mapped to its nodes once (setup): per frame,
/// assemble() gives the force on the free dofs with no allocation.
class BodyLoads {
 public:
  /// `body` must outlive this.
  ///   per_load  #L nodal weights on body.mesh()'s nodes, one per load
  BodyLoads(const ElasticBody& body, std::vector<NodalWeights> per_load);

  /// f_free = 0 but, for each load l and entry k, weights_lk values[l] on the free
  /// dofs of node nodes_lk (a share on a clamped node goes to the support).
  ///   values  #L, f_free  #free dofs (resized if needed). No allocation.
  void assemble(const std::vector<Eigen::Vector3d>& values, Eigen::VectorXd& f_free) const;
  /// The free dofs assemble() may make nonzero, sorted and unique.
  const std::vector<int>& loaded_free_dofs() const { return loaded_free_dofs_; }
  size_t size() const { return per_load_.size(); }
  const NodalWeights& load(size_t l) const { return per_load_[l]; }
  const ElasticBody& body() const { return body_; }

 private:
  const ElasticBody& body_;
  std::vector<NodalWeights> per_load_;
  std::vector<int> loaded_free_dofs_;
};

}  // namespace tb
