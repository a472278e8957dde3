// A linear-elastic body on a tet mesh with clamped nodes and, optionally, groups of
// nodes whose displacement is prescribed each frame (a grasp, a plate), assembled
// once: the stiffness K of eq. (11), which dofs are free, K restricted to them, and
// what the prescribed values add to the right-hand side (Dirichlet conditions:
// K_ff u_f = f_f - K_fp u_p). What every way of solving K u = f shares
// (elastic_solve.h); the fine FEM and the coarse meshes each hold one. The forces
// the body exerts on each group and on the support (reactions) come from the
// same K.
#pragma once

#include <Eigen/SparseCore>
#include <vector>

#include "load_mapping.h"

namespace tb {
class ElasticSolve;
}
#include "material.h"
#include "mesh_types.h"

namespace tb {

/// Limits OpenBLAS (under CHOLMOD), OpenMP and deal.II's task pool (TBB, used when
/// a Triangulation is built) to one thread, so that every timing the project
/// reports is single-threaded. Call once at program start.
void use_one_thread();

/// OpenBLAS's threads (the dense kernels of CHOLMOD's supernodal factorisation) set
/// to `threads` for this object's lifetime, the previous count again after: a
/// reference solve on a large mesh may take the machine's cores while every other
/// timing stays single-threaded. Nothing is called when the count does not change.
class BlasThreads {
 public:
  explicit BlasThreads(int threads);
  ~BlasThreads();
  BlasThreads(const BlasThreads&) = delete;
  BlasThreads& operator=(const BlasThreads&) = delete;

 private:
  int previous_, threads_;
};

/// Nodes whose displacement is prescribed together each frame: every listed
/// component of every node gets that component of the group's value (a rigid
/// translation); the other components stay free (a plate that slides).
struct PrescribedGroup {
  std::vector<int> nodes;                      ///< #N node indices, distinct, none clamped
  bool components[3] = {true, true, true};     ///< which of x, y, z are prescribed
};

/// A zero-length spring from a node to a point that moves with a tool (a compliant
/// grasp's pad, tool_placement.h): stiffness k, N/m, alike in x, y and z. It adds
/// k |u - d|^2 / 2 to the body's energy: k I to K at the node, and k d to the
/// force, which the caller supplies as a load (weights k, value d).
struct NodeSpring {
  int node = 0;
  double stiffness = 0;
};

class ElasticBody {
 public:
  /// Assembles K (deal.II, stiffness_assembly.h) and removes the clamped and the
  /// prescribed dofs from the free ones.
  ///   clamped     #V flags, 1 = zero displacement
  ///   prescribed  #G groups (a node in at most one group and not clamped)
  /// Throws std::invalid_argument if nothing is clamped or prescribed (K is
  /// singular), if everything is, or if a group names a clamped node, a node twice
  /// or none. (Prescribed groups alone must hold the body's rigid motions.)
  ///   springs  zero-length springs on free nodes (NodeSpring), in K_full and K_free;
  ///            a node listed twice gets the sum. Throws std::invalid_argument for a
  ///            spring on a clamped or prescribed node, or one not positive and finite.
  ElasticBody(const TetMesh& mesh, const Material& material, const std::vector<char>& clamped,
              std::vector<PrescribedGroup> prescribed = {}, const std::vector<NodeSpring>& springs = {});

  const TetMesh& mesh() const { return mesh_; }
  const Material& material() const { return material_; }
  /// The full (unconstrained) 3 #V by 3 #V stiffness; dof 3 * node + component.
  const Eigen::SparseMatrix<double>& full_stiffness() const { return K_full_; }
  /// K on the free dofs only (both triangles stored).
  const Eigen::SparseMatrix<double>& free_stiffness() const { return K_free_; }
  int dofs() const { return static_cast<int>(full_to_free_.size()); }
  int free_dofs() const { return static_cast<int>(free_to_full_.size()); }
  /// The free index of a full dof, -1 when clamped or prescribed.
  int free_index(int dof) const { return full_to_free_[static_cast<size_t>(dof)]; }

  /// u (3 #V) -> u_free, and back (clamped dofs set to 0 when u is resized; the
  /// other non-free dofs left as they are). No allocation when the output already
  /// has its size.
  void to_free(const Eigen::VectorXd& u, Eigen::VectorXd& u_free) const;
  void to_full(const Eigen::VectorXd& u_free, Eigen::VectorXd& u) const;

  const std::vector<PrescribedGroup>& prescribed_groups() const { return groups_; }
  /// Per node, the summed stiffness of its springs (N/m; #V, 0 where none): what a
  /// nonlinear strategy adds to its internal force (k u) and tangent (k I), since
  /// it assembles its own. Empty when the body has no spring.
  const Eigen::VectorXd& spring_stiffness() const { return spring_stiffness_; }
  /// f_free -= K_fp u_p, u_p the prescribed dofs at `group_values` (#G, one per
  /// group). No allocation.
  void subtract_prescribed(const std::vector<Eigen::Vector3d>& group_values, Eigen::VectorXd& f_free) const;
  /// The free dofs subtract_prescribed() may change, sorted.
  const std::vector<int>& prescribed_coupled_rows() const { return coupled_rows_; }
  /// Sets the prescribed dofs of u (3 #V) to `group_values`.
  void set_prescribed(const std::vector<Eigen::Vector3d>& group_values, Eigen::VectorXd& u) const;
  /// The force the body exerts on each group (#G) and on the clamped nodes
  /// (`support`), N: at each constrained dof c, f_c - f_int,c, summed over the
  /// group's dofs, where f (3 #V) is the external nodal force (the share of a load
  /// that lands on a constrained node) and f_int the internal force: K u, or
  /// `internal_force` (3 #V) when given (a nonlinear law). Components a group does
  /// not prescribe are 0. No allocation when `groups` has its size.
  void reactions(const Eigen::VectorXd& u, const Eigen::VectorXd& f, std::vector<Eigen::Vector3d>& groups,
                 Eigen::Vector3d& support, const Eigen::VectorXd* internal_force = nullptr) const;

 private:
  TetMesh mesh_;
  Material material_;
  Eigen::SparseMatrix<double> K_full_, K_free_;
  std::vector<int> full_to_free_;  ///< -1 for clamped and prescribed dofs
  std::vector<int> free_to_full_;
  std::vector<PrescribedGroup> groups_;
  Eigen::VectorXd spring_stiffness_;
  std::vector<int> prescribed_dof_, prescribed_group_;  ///< each prescribed dof and its group
  std::vector<int> clamped_dof_;                        ///< every clamped dof
  Eigen::SparseMatrix<double> K_fp_;                    ///< free rows by prescribed dofs
  std::vector<int> coupled_rows_;                       ///< rows of K_fp with a nonzero
  mutable Eigen::VectorXd u_p_;                         ///< work: the prescribed values
};

/// u (3 #V): the body's response to a unit translation along component c of the
/// held components of prescribed group g, the other groups at rest: K_ff u_f =
/// -K_fp e solved by `solve` (linear), the held dofs set. The columns a
/// precomputation superposes (ElasticFrame, PrecomputedResponse). Set-up only.
void unit_translation_response(const ElasticBody& body, ElasticSolve& solve, size_t g, int c, Eigen::VectorXd& u);

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
  /// f (3 #V) = the loads' nodal forces on every dof, constrained ones included
  /// (for reactions). No allocation once f has its size.
  void assemble_full(const std::vector<Eigen::Vector3d>& values, Eigen::VectorXd& f) const;
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

/// One static frame of a linear-elastic body: the loads assembled, the prescribed
/// displacements applied (K_ff u_f = f_f - K_fp u_p), solved by `solve`, and the
/// reactions measured: what the fem, embedded and hybrid models share. The body,
/// the loads and the solve must outlive it. With a factorised solve (direct), each
/// prescribed group's response to a unit translation, K_ff w = -K_fp e, is solved
/// once here and a frame adds the groups' values times their responses to the
/// loads' solution: the frame's forward substitution visits the loads' rows only,
/// not every row the held nodes couple to (a plate's face), so a tool costs about
/// what a point force does (docs/architecture.md, "What the layers cost a frame").
class ElasticFrame {
 public:
  ElasticFrame(const ElasticBody& body, const BodyLoads& loads, ElasticSolve& solve);
  /// u (3 #V, the previous frame's in: a warm start) for this frame's values.
  ///   load_values   #L, one per load; group_values  #G, one per prescribed group
  /// No allocation after the first call.
  void step(const std::vector<Eigen::Vector3d>& load_values, const std::vector<Eigen::Vector3d>& group_values,
            Eigen::VectorXd& u);
  /// After step(): the force the body exerts on each prescribed group (#G) and
  /// on its support, N (ElasticBody::reactions).
  const std::vector<Eigen::Vector3d>& group_forces() const { return group_forces_; }
  const Eigen::Vector3d& support_force() const { return support_force_; }

 private:
  const ElasticBody& body_;
  const BodyLoads& loads_;
  ElasticSolve& solve_;
  std::vector<int> rows_;  ///< free dofs the right-hand side may touch
  Eigen::VectorXd f_free_, f_full_, u_free_;
  /// Factorised solves: per group, the free dofs' response to a unit translation
  /// along x, y, z (#free by 3; zero columns for components it does not hold).
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, 3>> group_response_;
  std::vector<Eigen::Vector3d> group_forces_;
  Eigen::Vector3d support_force_ = Eigen::Vector3d::Zero();
};

}  // namespace tb
