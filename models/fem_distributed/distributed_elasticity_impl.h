// The deal.II state of DistributedElasticity, shared by its two translation units
// (distributed_elasticity.cc: mesh, dofs, linear solve; neo_hookean_solve.cc: the
// Newton solve). Include only from those.
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
  const MaterialLawInfo* law;  ///< settings.law, from the table
  const TetMesh* mesh = nullptr;  ///< the caller's; used in the constructor only
  dealii::parallel::fullydistributed::Triangulation<3> tria;
  dealii::FESystem<3> fe;
  dealii::MappingFE<3> mapping;
  dealii::QGaussSimplex<3> quadrature;  ///< degree-exact for B^T D B
  dealii::DoFHandler<3> dof_handler;
  dealii::IndexSet owned, relevant;
  std::vector<unsigned> component;  ///< vector component of each cell shape function
  /// Dirichlet values (prescribed or zero), and the same dofs held at zero
  /// (Newton increments).
  dealii::AffineConstraints<double> constraints, zero_constraints;
  std::vector<Eigen::Vector3d> owned_support_points;  ///< by position in `owned`
  std::vector<unsigned> owned_components;             ///< by position in `owned`
  std::vector<int> cell_tet;                          ///< by active cell index: the TetMesh tet (owned cells)
  std::vector<std::array<int, 4>> cell_nodes;         ///< by active cell index: TetMesh node of each vertex

  dealii::TrilinosWrappers::SparseMatrix K;  ///< linear: stiffness; neo-Hookean: tangent
  Vector lift;                               ///< linear: right-hand side of the prescribed values
  dealii::TrilinosWrappers::PreconditionAMG amg;
  std::vector<double> rigid_modes;  ///< 6 columns of #owned: the near null space (must outlive amg)
  Vector u;                         ///< the solution, owned dofs
  Vector f_previous;                ///< neo-Hookean: the last converged external force
  DistributedStats stats;

  /// f += the load's consistent nodal forces (eq. 10 with the cell's shape functions).
  void add_load(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force, Vector& f) const;
  /// Builds the AMG hierarchy of K with the rigid-body modes as near null space.
  void build_amg();
  /// CG on K x = b from x; returns iterations. Throws std::runtime_error on failure.
  int cg(const Vector& b, Vector& x, double tolerance);
  void solve_linear(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force);
  void solve_nonlinear(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force);  // nonlinear_solve.cc
};

}  // namespace tb
