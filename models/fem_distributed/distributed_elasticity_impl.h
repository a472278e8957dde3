// The deal.II state of DistributedElasticity, shared by its two translation units
// (distributed_elasticity.cc: mesh, dofs, linear solve, reactions, probes;
// nonlinear_solve.cc: the Newton solve). Include only from those.
#pragma once

#include <deal.II/base/index_set.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <array>
#include <memory>
#include <unordered_map>
#include <vector>

#include "distributed_elasticity.h"
#include "elasticity_cell.h"
#include "material_laws.h"

namespace tb {

struct DistributedElasticity::Impl {
  using Cell = dealii::DoFHandler<3>::active_cell_iterator;
  using Vector = dealii::TrilinosWrappers::MPI::Vector;

  Impl(MPI_Comm c, const DistributedSettings& s, const Material& m);

  MPI_Comm comm;
  DistributedSettings settings;
  LameParameters lame;
  double density;              ///< kg/m^3, of the body force rho g
  const MaterialLawInfo* law;  ///< settings.law, from the table
  Eigen::Index n_tets = 0;     ///< of the caller's TetMesh
  dealii::parallel::fullydistributed::Triangulation<3> tria;
  dealii::FESystem<3> fe;
  dealii::MappingFE<3> mapping;
  dealii::QGaussSimplex<3> quadrature;  ///< degree-exact for B^T D B
  dealii::DoFHandler<3> dof_handler;
  dealii::IndexSet owned, relevant;
  std::vector<unsigned> component;  ///< vector component of each cell shape function
  /// Dirichlet values (prescribed or zero; a group's dofs at zero, their values
  /// set per solve), and the same dofs held at zero (Newton increments).
  dealii::AffineConstraints<double> constraints, zero_constraints;
  std::vector<PrescribedGroup> groups;
  /// A dof a group holds: which group, which component.
  struct HeldDof {
    dealii::types::global_dof_index dof;
    int group;
    unsigned component;
  };
  std::vector<HeldDof> held_relevant;  ///< the groups' dofs among the locally relevant ones
  std::vector<HeldDof> held_owned;     ///< the groups' dofs among the owned ones
  std::unordered_map<dealii::types::global_dof_index, int> group_of_dof;  ///< relevant held dof -> group
  /// Each group's values at the state u holds (the last converged solve's).
  std::vector<Eigen::Vector3d> group_values;
  /// Linear law: column 3 g + c is -K_fp restricted to group g's component-c dofs,
  /// times one (the right-hand side a unit value of that component adds).
  std::vector<dealii::TrilinosWrappers::MPI::Vector> group_lift;
  std::vector<Cell> constrained_cells;     ///< owned cells with a constrained dof (reactions)
  std::vector<Eigen::Vector3d> reactions;  ///< each group's, then the support's (N)
  /// The probes in this rank's cells: the probe's row, its cell, the cell's shape
  /// functions at its reference point.
  struct OwnedProbe {
    Eigen::Index row;
    Cell cell;
    std::vector<double> shape;
  };
  std::vector<OwnedProbe> probes;
  Eigen::Index probe_count = 0;
  std::vector<Eigen::Vector3d> owned_support_points;  ///< by position in `owned`
  std::vector<unsigned> owned_components;             ///< by position in `owned`
  std::vector<int> cell_tet;                          ///< by active cell index: the TetMesh tet (owned and ghost cells)
  std::vector<std::array<int, 4>> cell_nodes;         ///< by active cell index: TetMesh node of each vertex

  dealii::TrilinosWrappers::SparseMatrix K;  ///< linear: stiffness; neo-Hookean: tangent
  Vector lift;                               ///< linear: right-hand side of the prescribed values
  dealii::TrilinosWrappers::PreconditionAMG amg;
  std::vector<double> rigid_modes;  ///< 6 columns of #owned: the near null space (must outlive amg)
  Vector u;                         ///< the solution, owned dofs
  Vector f_previous;                ///< nonlinear laws: the last converged external force
  /// The body force's nodal forces per unit acceleration along x, y, z (rho int N_i
  /// over the reference cells, zero on constrained dofs): built at the first solve
  /// with a nonzero acceleration, so that a run without gravity holds none.
  std::vector<Vector> body_unit;
  DistributedStats stats;

  /// f += the load's consistent nodal forces (eq. 10 with the cell's shape functions).
  void add_load(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force, Vector& f) const;
  /// The load's consistent nodal forces on `cell` (zero where none acts): the
  /// per-cell part of add_load.
  void cell_load(const Cell& cell, const std::vector<const LoadPoint*>& points, const Eigen::Vector3d& force,
                 dealii::Vector<double>& fe_force) const;
  /// f += the body force rho g (elasticity_cell.h's body_force_cell over the owned
  /// cells), a dead load like the point loads. Collective.
  void add_body_force(const Eigen::Vector3d& g, Vector& f);
  /// u with its ghost entries (locally relevant dofs).
  Vector ghosted(const Vector& owned_vector) const;
  /// Sets every owned dof a group holds in x to its group's value in `values`
  /// (zero when `values` is null); x compressed.
  void set_held(Vector& x, const std::vector<Eigen::Vector3d>* values) const;
  /// reactions from u, the loads and the law (after a solve). Collective.
  void measure_reactions(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force, const Eigen::Vector3d& g);
  /// Builds the AMG hierarchy of K with the rigid-body modes as near null space.
  void build_amg();
  /// CG on K x = b from x; returns iterations. Throws std::runtime_error on failure.
  int cg(const Vector& b, Vector& x, double tolerance);
  /// K_ff u_f = f_f - K_fp u_p; f the external force (the load and the body force).
  void solve_linear(const Vector& f_external, const std::vector<Eigen::Vector3d>& values);
  void solve_nonlinear(const Vector& f_external, const std::vector<Eigen::Vector3d>& values);  // nonlinear_solve.cc
};

}  // namespace tb
