// The fine FEM distributed with MPI: the reference solve at 10^6 dofs
// and beyond, on deal.II's own parallel machinery. A fully distributed simplex
// triangulation is built from the tet mesh (every rank holds the same TetMesh and
// keeps its part plus a ghost layer), P1 or P2 vector elements (FE_SimplexP), and
// Trilinos matrices and vectors; each solve is CG preconditioned by smoothed-
// aggregation algebraic multigrid (ML) with the six rigid-body modes as its near
// null space. Linear elasticity (the element integrals of eq. 9, the same code as
// the serial real-time path, elasticity_cell.h) or any hyperelastic law of the
// table (Newton with load stepping), under point loads, tractions and a body force
// (gravity). Besides the support, groups of nodes whose displacement is
// prescribed each frame (a grasp, a plate: models/tool_placement.h) are
// inhomogeneous Dirichlet constraints; the reactions on them and on the support,
// and the field at interior points (probes), are measured. A plain interface: the
// deal.II types stay in the .cc files.
#pragma once

#include <mpi.h>

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "elastic_body.h"
#include "material.h"
#include "mesh_types.h"
#include "surface_load.h"

namespace tb {

struct DistributedSettings {
  int degree = 1;  ///< polynomial degree of FE_SimplexP: 1 or 2
  /// A law of material_laws() (numerics/materials): "linear" is one linear solve per
  /// frame; any other, Newton with load increments (nonlinear_solve.cc).
  std::string law = "linear";
  double cg_tolerance = 1e-10;  ///< relative residual of each linear solve
  // Nonlinear laws only:
  int load_steps = 1;  ///< load increments per solve (halved on failure)
  /// Converged when |R| (free dofs) <= tolerance times the forces in play: the
  /// larger of |f_ext| and |f_int| over every dof (reactions included) at the
  /// increment's first state, as the serial newton solve (newton_solve.cc) measures
  /// them, so that a solve driven by prescribed displacements alone has a scale.
  double newton_tolerance = 1e-9;
  int max_newton_iterations = 30;   ///< per increment, before it is halved
  int max_increment_halvings = 10;  ///< then the solve fails
};

/// What the last solve did.
struct DistributedStats {
  long long dofs = 0, cells = 0;                ///< global counts
  int cg_iterations = 0;                        ///< summed over the solve's linear systems
  long long supported_dofs = 0, held_dofs = 0;  ///< global counts: held by the support, by the groups
  int newton_iterations = 0;                    ///< nonlinear laws: summed over increments
  int load_increments = 0;                      ///< nonlinear laws: accepted increments
  int increment_halvings = 0;                   ///< nonlinear laws: increments cut after a failed Newton
  double condition_estimate = 0;                ///< of the preconditioned system, from CG's Lanczos (last linear solve)
  // Wall-clock seconds of the phases (rank 0's): setup, then the last solve.
  double mesh_s = 0, dofs_s = 0, assembly_s = 0, preconditioner_s = 0, solve_s = 0;
};

class DistributedElasticity {
 public:
  using Predicate = std::function<bool(const Eigen::Vector3d&)>;
  using Field = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

  /// Builds the distributed mesh, dofs and constraints; assembles K and the AMG
  /// hierarchy (linear law). Collective over `comm`; every rank passes the same
  /// mesh. A dof is prescribed when support(its support point) is true (P1: the
  /// nodes; P2: nodes and edge midpoints), to zero or to prescribed(x) if given
  /// (linear law only).
  ///   mesh  #V by 3 V, #T by 4 positively oriented T
  /// Throws std::invalid_argument for a degree other than 1 or 2 or a prescribed
  /// field with a nonlinear law.
  ///
  /// `groups` (a grasp, a plate: fine_volume_group in tool_placement.h) hold their
  /// nodes' listed components at the value solve() gives each group. With P2, a
  /// group also holds the midside dofs of the boundary edges both of whose nodes it
  /// holds: the held part of the surface is then the same as with P1 (where the
  /// field on such an edge, or on a boundary face all of whose nodes are held, is
  /// the held value) and follows the tool exactly there; a midside dof is chosen
  /// from the group's nodes and the mesh alone, never from a box or a radius, so
  /// that every model holds what tool_vertices() chose. Boundary edges are the
  /// edges of tet faces that belong to one tet only.
  /// Throws std::invalid_argument, besides the above, when a group is empty, names
  /// a node outside the mesh or a node another group holds in the same component,
  /// or holds a dof the support clamps, and when neither the support nor a group
  /// holds a dof.
  DistributedElasticity(const TetMesh& mesh, const Material& material, const Predicate& support,
                        const DistributedSettings& settings, MPI_Comm comm, const Field& prescribed = {},
                        const std::vector<PrescribedGroup>& groups = {});
  ~DistributedElasticity();
  DistributedElasticity(const DistributedElasticity&) = delete;
  DistributedElasticity& operator=(const DistributedElasticity&) = delete;

  /// Solves for the load: weight_k * force at each point (surface_load.h), and the
  /// body force of acceleration `gravity` (m/s^2): the force density rho g of the
  /// material's density over the reference configuration, a dead load, whose nodal
  /// forces are int rho g N_i dV (P1: rho g V / 4 per node of each tet, the serial
  /// FEM's consistent masses), with each group's held components at
  /// group_values[g] (#groups, m), the next solve starting from this one
  /// (nonlinear laws: its increments go from the previous loads and group values
  /// to these, as the serial newton solve's, nonlinear_solve.cc). Collective.
  /// Throws std::invalid_argument if group_values does not have one value per
  /// group, or a nonzero gravity meets a density that is not positive, and
  /// std::runtime_error if CG or Newton fail (the state is then that of the last
  /// converged solve).
  void solve(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force,
             const std::vector<Eigen::Vector3d>& group_values = {},
             const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero());

  /// Displacement at mesh nodes `nodes` (#nodes by 3), the same on every rank.
  /// Collective.
  Points node_displacements(const std::vector<int>& nodes) const;

  /// After solve(): the force the body exerts on each group (#groups) and then on
  /// the support (the dofs the support predicate holds), N, the same on every rank:
  /// at each constrained dof, the loads' share there (the body force's included)
  /// minus the internal force (K u, or the law's f_int(u)), summed over the group's
  /// dofs; a component a group does not hold is 0 (ElasticBody::reactions, the
  /// serial models' measure).
  const std::vector<Eigen::Vector3d>& reactions() const;

  /// Fixes the points probe_displacements() reads: point p (row p of `points`,
  /// rest configuration) in the TetMesh tet tets[p] (place_probes in
  /// tool_placement.h); each rank keeps those in its own cells. Every rank passes
  /// the same points. Throws std::invalid_argument if the sizes differ or a tet
  /// index is outside the mesh.
  ///   points  #P by 3, tets  #P
  void set_probes(const Points& points, const std::vector<int>& tets);
  /// The displacement at the probes (#P by 3), the same on every rank: the FE field
  /// (P1 or P2) of the cell of the probe's tet at its reference point, from the rank
  /// that owns the cell. Collective.
  Points probe_displacements() const;

  const DistributedStats& stats() const;

  struct Impl;  ///< deal.II state (distributed_elasticity_impl.h)

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace tb
