// The fine FEM distributed with MPI: the reference solve at 10^6 dofs
// and beyond, on deal.II's own parallel machinery. A fully distributed simplex
// triangulation is built from the tet mesh (every rank holds the same TetMesh and
// keeps its part plus a ghost layer), P1 or P2 vector elements (FE_SimplexP), and
// Trilinos matrices and vectors; each solve is CG preconditioned by smoothed-
// aggregation algebraic multigrid (ML) with the six rigid-body modes as its near
// null space. Linear elasticity (the element integrals of eq. 9, the same code as
// the serial real-time path, elasticity_cell.h) or a compressible neo-Hookean
// solid (Newton with load stepping). A plain interface: the deal.II types stay in
// the .cc files.
#pragma once

#include <mpi.h>

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

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
  int load_steps = 1;               ///< load increments per solve (halved on failure)
  double newton_tolerance = 1e-9;   ///< converged when |R| <= tolerance |f_ext| (free dofs)
  int max_newton_iterations = 30;   ///< per increment, before it is halved
  int max_increment_halvings = 10;  ///< then the solve fails
};

/// What the last solve did.
struct DistributedStats {
  long long dofs = 0, cells = 0;  ///< global counts
  int cg_iterations = 0;          ///< summed over the solve's linear systems
  int newton_iterations = 0;      ///< neo-Hookean: summed over increments
  int load_increments = 0;        ///< neo-Hookean: accepted increments
  int increment_halvings = 0;     ///< neo-Hookean: increments cut after a failed Newton
  double condition_estimate = 0;  ///< of the preconditioned system, from CG's Lanczos (last linear solve)
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
  /// Throws std::invalid_argument for a degree other than 1 or 2, an empty
  /// support, or a prescribed field with the neo-Hookean law.
  DistributedElasticity(const TetMesh& mesh, const Material& material, const Predicate& support,
                        const DistributedSettings& settings, MPI_Comm comm, const Field& prescribed = {});
  ~DistributedElasticity();
  DistributedElasticity(const DistributedElasticity&) = delete;
  DistributedElasticity& operator=(const DistributedElasticity&) = delete;

  /// Solves for the load: weight_k * force at each point (surface_load.h), the
  /// next solve starting from this one (neo-Hookean: its increments go from the
  /// previous load to this one). Collective. Throws std::runtime_error if CG or
  /// Newton fail (the state is then that of the last converged solve).
  void solve(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force);

  /// Displacement at mesh nodes `nodes` (#nodes by 3), the same on every rank.
  /// Collective.
  Points node_displacements(const std::vector<int>& nodes) const;

  const DistributedStats& stats() const;

  struct Impl;  ///< deal.II state (distributed_elasticity_impl.h)

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace tb
