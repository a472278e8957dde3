// The distributed fine FEM, narrated:
//  1. Partition: every rank orders the tets along a Morton curve of their
//     centroids and takes one contiguous chunk (deterministic, the same on every
//     rank since every rank holds the same TetMesh).
//  2. Mesh: a parallel::fullydistributed::Triangulation from a description of the
//     rank's tets plus the ghost layer (tets sharing a node with them); a coarse
//     cell's id is its tet's index, which ties deal.II's cells to the TetMesh.
//  3. Dofs: FESystem(FE_SimplexP(degree), 3); a dof is prescribed when its support
//     point (a node, or an edge midpoint for P2, computed exactly from the nodes)
//     is in the support.
//  4. K from the element matrices of eq. (9) (elasticity_cell.h, the serial path's
//     own function), Trilinos CrsMatrix; AMG (ML smoothed aggregation) with the
//     rigid-body modes as near null space, built once.
//  5. Each solve: f from the load points (eq. 10 with the cell's shape functions),
//     CG warm-started from the previous solution.
#include "distributed_elasticity.h"

#include <Epetra_MultiVector.h>
#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/tria_description.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparsity_tools.h>

#include <Teuchos_ParameterList.hpp>
#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "distributed_elasticity_impl.h"

namespace tb {
using namespace dealii;

namespace {

/// x, y, z (21 bits each) interleaved.
uint64_t morton_key(uint32_t x, uint32_t y, uint32_t z) {
  auto spread = [](uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
  };
  return spread(x) | spread(y) << 1 | spread(z) << 2;
}

/// Owner rank of each tet: contiguous chunks of the tets in Morton order.
std::vector<unsigned> partition_tets(const TetMesh& m, unsigned parts) {
  const size_t n = static_cast<size_t>(m.T.rows());
  std::vector<unsigned> owner(n, 0);
  if (parts <= 1) return owner;
  const Eigen::RowVector3d lo = m.V.colwise().minCoeff(), hi = m.V.colwise().maxCoeff();
  const Eigen::RowVector3d scale = (2097151.0 / (hi - lo).array().max(1e-300)).matrix();
  std::vector<std::pair<uint64_t, int>> keys(n);
  for (size_t t = 0; t < n; ++t) {
    Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
    for (int k = 0; k < 4; ++k) c += m.V.row(m.T(static_cast<Eigen::Index>(t), k));
    const Eigen::RowVector3d q = ((c / 4 - lo).array() * scale.array()).matrix();
    keys[t] = {morton_key(static_cast<uint32_t>(q(0)), static_cast<uint32_t>(q(1)), static_cast<uint32_t>(q(2))),
               static_cast<int>(t)};
  }
  std::sort(keys.begin(), keys.end());
  for (size_t i = 0; i < n; ++i) owner[static_cast<size_t>(keys[i].second)] = static_cast<unsigned>(i * parts / n);
  return owner;
}

/// The rank's part of the mesh for parallel::fullydistributed::Triangulation: its
/// tets and the ghost layer, with local vertex numbers in increasing node order.
TriangulationDescription::Description<3, 3> describe(const TetMesh& m, const std::vector<unsigned>& owner,
                                                     unsigned rank, MPI_Comm comm) {
  const size_t n_tets = static_cast<size_t>(m.T.rows());
  std::vector<char> touched(static_cast<size_t>(m.V.rows()), 0);
  for (size_t t = 0; t < n_tets; ++t)
    if (owner[t] == rank)
      for (int k = 0; k < 4; ++k) touched[static_cast<size_t>(m.T(static_cast<Eigen::Index>(t), k))] = 1;
  std::vector<int> relevant_tets;
  for (size_t t = 0; t < n_tets; ++t) {
    bool near = owner[t] == rank;
    for (int k = 0; k < 4 && !near; ++k) near = touched[static_cast<size_t>(m.T(static_cast<Eigen::Index>(t), k))];
    if (near) relevant_tets.push_back(static_cast<int>(t));
  }
  std::vector<int> local(static_cast<size_t>(m.V.rows()), -1);
  for (int t : relevant_tets)
    for (int k = 0; k < 4; ++k) local[static_cast<size_t>(m.T(t, k))] = 0;
  TriangulationDescription::Description<3, 3> d;
  unsigned next = 0;
  for (size_t v = 0; v < local.size(); ++v)
    if (local[v] == 0) {
      local[v] = static_cast<int>(next++);
      const Eigen::Index i = static_cast<Eigen::Index>(v);
      d.coarse_cell_vertices.emplace_back(m.V(i, 0), m.V(i, 1), m.V(i, 2));
    }
  d.cell_infos.resize(1);
  d.coarse_cells.reserve(relevant_tets.size());
  d.cell_infos[0].reserve(relevant_tets.size());
  for (int t : relevant_tets) {
    CellData<3> cell(4);
    for (unsigned k = 0; k < 4; ++k) cell.vertices[k] = static_cast<unsigned>(local[static_cast<size_t>(m.T(t, k))]);
    d.coarse_cells.push_back(cell);
    d.coarse_cell_index_to_coarse_cell_id.push_back(static_cast<types::coarse_cell_id>(t));
    TriangulationDescription::CellData<3> info;
    info.id = CellId(static_cast<types::coarse_cell_id>(t), std::vector<std::uint8_t>()).to_binary<3>();
    info.subdomain_id = owner[static_cast<size_t>(t)];
    info.level_subdomain_id = numbers::artificial_subdomain_id;
    info.manifold_id = numbers::flat_manifold_id;
    info.manifold_line_ids.fill(numbers::flat_manifold_id);
    info.manifold_quad_ids.fill(numbers::flat_manifold_id);
    d.cell_infos[0].push_back(info);
  }
  d.comm = comm;
  d.settings = TriangulationDescription::Settings::default_setting;
  d.smoothing = Triangulation<3>::none;
  return d;
}

Eigen::Vector3d to_eigen(const Point<3>& p) { return {p[0], p[1], p[2]}; }

/// Seconds since `start`, which is reset.
double lap(std::chrono::steady_clock::time_point& start) {
  const auto now = std::chrono::steady_clock::now();
  const double s = std::chrono::duration<double>(now - start).count();
  start = now;
  return s;
}

}  // namespace

DistributedElasticity::Impl::Impl(MPI_Comm c, const DistributedSettings& s, const Material& m)
    : comm(c),
      settings(s),
      lame(lame_parameters(m)),
      law(&find_material_law(s.law)),
      tria(c),
      fe(FE_SimplexP<3>(static_cast<unsigned>(s.degree)), 3),
      mapping(FE_SimplexP<3>(1)),
      quadrature(static_cast<unsigned>(s.degree)) {}

DistributedElasticity::DistributedElasticity(const TetMesh& mesh, const Material& material, const Predicate& support,
                                             const DistributedSettings& settings, MPI_Comm comm,
                                             const Field& prescribed) {
  if (settings.degree != 1 && settings.degree != 2)
    throw std::invalid_argument("distributed FEM: degree " + std::to_string(settings.degree) +
                                " is not supported (1: P1, 2: P2)");
  if (prescribed && settings.law != "linear")
    throw std::invalid_argument("distributed FEM: prescribed displacements need the linear law");
  impl_ = std::make_unique<Impl>(comm, settings, material);
  Impl& d = *impl_;
  const unsigned rank = Utilities::MPI::this_mpi_process(comm), ranks = Utilities::MPI::n_mpi_processes(comm);

  // 1-2. Partition and the distributed mesh.
  auto clock = std::chrono::steady_clock::now();
  d.tria.create_triangulation(describe(mesh, partition_tets(mesh, ranks), rank, comm));
  d.stats.cells = static_cast<long long>(d.tria.n_global_active_cells());
  d.stats.mesh_s = lap(clock);

  // 3. Dofs and their support points, computed exactly from the nodes
  //    (x = sum_k lambda_k v_k with the unit support point's barycentrics).
  d.dof_handler.reinit(d.tria);
  d.dof_handler.distribute_dofs(d.fe);
  d.owned = d.dof_handler.locally_owned_dofs();
  DoFTools::extract_locally_relevant_dofs(d.dof_handler, d.relevant);
  d.stats.dofs = static_cast<long long>(d.dof_handler.n_dofs());
  const unsigned n = d.fe.n_dofs_per_cell();
  d.component.resize(n);
  for (unsigned i = 0; i < n; ++i) d.component[i] = d.fe.system_to_component_index(i).first;
  std::vector<std::array<double, 4>> lambda(n);
  for (unsigned i = 0; i < n; ++i) {
    const Point<3> xi = d.fe.unit_support_point(i);
    lambda[i] = {{1 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]}};
  }
  d.constraints.reinit(d.relevant);
  d.zero_constraints.reinit(d.relevant);
  d.owned_support_points.resize(d.owned.n_elements());
  d.owned_components.resize(d.owned.n_elements());
  d.cell_tet.assign(d.tria.n_active_cells(), -1);
  d.cell_nodes.resize(d.tria.n_active_cells());
  std::vector<types::global_dof_index> ids(n);
  long long prescribed_here = 0;
  for (const auto& cell : d.dof_handler.active_cell_iterators()) {
    if (cell->is_artificial()) continue;
    cell->get_dof_indices(ids);
    for (unsigned i = 0; i < n; ++i) {
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (unsigned k = 0; k < 4; ++k) x += lambda[i][k] * to_eigen(cell->vertex(k));
      if (d.owned.is_element(ids[i])) {
        d.owned_support_points[d.owned.index_within_set(ids[i])] = x;
        d.owned_components[d.owned.index_within_set(ids[i])] = d.component[i];
      }
      if (d.constraints.is_constrained(ids[i]) || !support(x)) continue;
      d.constraints.add_line(ids[i]);
      d.zero_constraints.add_line(ids[i]);
      if (prescribed) d.constraints.set_inhomogeneity(ids[i], prescribed(x)[d.component[i]]);
      prescribed_here += d.owned.is_element(ids[i]);
    }
    if (!cell->is_locally_owned()) continue;
    // The TetMesh nodes of the cell's vertices, matched by position.
    const int tet = static_cast<int>(cell->id().get_coarse_cell_id());
    d.cell_tet[cell->active_cell_index()] = tet;
    for (unsigned k = 0; k < 4; ++k) {
      int node = -1;
      for (int j = 0; j < 4; ++j)
        if (mesh.V.row(mesh.T(tet, j)).transpose() == to_eigen(cell->vertex(k))) node = mesh.T(tet, j);
      if (node < 0) throw std::logic_error("distributed FEM: a cell's vertex is not a node of its tet");
      d.cell_nodes[cell->active_cell_index()][k] = node;
    }
  }
  d.constraints.close();
  d.zero_constraints.close();
  long long prescribed_total = 0;
  MPI_Allreduce(&prescribed_here, &prescribed_total, 1, MPI_LONG_LONG, MPI_SUM, comm);
  if (prescribed_total == 0)
    throw std::invalid_argument("distributed FEM: the support selects no dof, so K is singular");

  d.stats.dofs_s = lap(clock);

  // 4. The sparsity of K, the matrix, and (linear law) its assembly and AMG.
  {
    DynamicSparsityPattern dsp(d.relevant);  // freed before the AMG's memory is taken
    DoFTools::make_sparsity_pattern(d.dof_handler, dsp, d.constraints, false);
    SparsityTools::distribute_sparsity_pattern(dsp, d.owned, comm, d.relevant);
    d.K.reinit(d.owned, d.owned, dsp, comm);
  }
  d.u.reinit(d.owned, comm);
  d.lift.reinit(d.owned, comm);
  d.f_previous.reinit(d.owned, comm);
  if (settings.law == "linear") {
    FEValues<3> fe_values(d.mapping, d.fe, d.quadrature, update_gradients | update_JxW_values);
    FullMatrix<double> Ke;
    dealii::Vector<double> no_force(n);
    std::vector<Tensor<1, 3>> grad;
    for (const auto& cell : d.dof_handler.active_cell_iterators()) {
      if (!cell->is_locally_owned()) continue;
      fe_values.reinit(cell);
      linear_elastic_cell_matrix(fe_values, d.component, LinearElastic(d.lame), Ke, grad);  // eq. (9)
      cell->get_dof_indices(ids);
      d.constraints.distribute_local_to_global(Ke, no_force, ids, d.K, d.lift);  // lift: -K g of prescribed g
    }
    d.K.compress(VectorOperation::add);
    d.lift.compress(VectorOperation::add);
    d.stats.assembly_s = lap(clock);
    d.build_amg();
    d.stats.preconditioner_s = lap(clock);
  }
}

DistributedElasticity::~DistributedElasticity() = default;

const DistributedStats& DistributedElasticity::stats() const { return impl_->stats; }

void DistributedElasticity::Impl::build_amg() {
  TrilinosWrappers::PreconditionAMG::AdditionalData data;
  data.elliptic = true;
  data.higher_order_elements = settings.degree > 1;
  data.smoother_sweeps = 2;
  data.aggregation_threshold = 1e-4;
  DoFTools::extract_constant_modes(dof_handler, ComponentMask(3, true), data.constant_modes);
  Teuchos::ParameterList parameters;
  std::unique_ptr<Epetra_MultiVector> constant_modes;
  data.set_parameters(parameters, constant_modes, K);
  // Plain (unsmoothed) aggregation. Smoothed aggregation's prolongator, with six
  // modes per aggregate, made the hierarchy cost 2.9 KB per dof (P1) and 4.5 KB
  // (P2); unsmoothed, 0.9 and 1.2 KB, and the setup 3x faster for P2, for twice
  // the CG iterations at about the same solve time (cube level 1, disc load: P1
  // 35 -> 68 iterations, 1.04 -> 0.99 s; P2 69 -> 112, 37 -> 35 s). Memory is
  // what bounds the finest level on one machine.
  parameters.set("aggregation: damping factor", 0.0);
  // The near null space of elasticity: three translations and three rotations
  // (about the body's centre, for conditioning), at each owned dof's support point.
  const size_t n_owned = owned_support_points.size();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& x : owned_support_points) centre += x;
  double count = static_cast<double>(n_owned);
  centre = Eigen::Vector3d(Utilities::MPI::sum(centre.x(), comm), Utilities::MPI::sum(centre.y(), comm),
                           Utilities::MPI::sum(centre.z(), comm)) /
           std::max(1.0, Utilities::MPI::sum(count, comm));
  rigid_modes.assign(6 * n_owned, 0.0);
  for (size_t p = 0; p < n_owned; ++p) {
    const unsigned c = owned_components[p];
    const Eigen::Vector3d x = owned_support_points[p] - centre;
    rigid_modes[c * n_owned + p] = 1;  // translation along c
    // Rotations about x, y, z: (0, -z, y), (z, 0, -x), (-y, x, 0).
    const double rot[3][3] = {{0, -x.z(), x.y()}, {x.z(), 0, -x.x()}, {-x.y(), x.x(), 0}};
    for (unsigned r = 0; r < 3; ++r) rigid_modes[(3 + r) * n_owned + p] = rot[r][c];
  }
  parameters.set("null space: type", "pre-computed");
  parameters.set("null space: dimension", 6);
  parameters.set("null space: vectors", rigid_modes.data());
  amg.initialize(K, parameters);
}

int DistributedElasticity::Impl::cg(const Vector& b, Vector& x, double tolerance) {
  const double b_norm = b.l2_norm();
  if (b_norm == 0) {
    x = 0;
    return 0;
  }
  SolverControl control(100000, tolerance * b_norm);
  SolverCG<Vector> solver(control);
  solver.connect_condition_number_slot([this](double c) { stats.condition_estimate = c; });
  try {
    solver.solve(K, x, b, amg);
  } catch (const SolverControl::NoConvergence& e) {
    std::ostringstream msg;
    msg << "distributed FEM: CG did not converge in " << e.last_step << " iterations (residual " << e.last_residual
        << ", wanted " << tolerance * b_norm << ")";
    throw std::runtime_error(msg.str());
  }
  return static_cast<int>(control.last_step());
}

void DistributedElasticity::Impl::add_load(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force,
                                           Vector& f) const {
  const unsigned n = fe.n_dofs_per_cell();
  dealii::Vector<double> fe_force(n);
  std::vector<types::global_dof_index> ids(n);
  std::unordered_map<int, std::vector<const LoadPoint*>> by_tet;
  for (const LoadPoint& p : load) by_tet[p.at.tet].push_back(&p);
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    const auto it = by_tet.find(cell_tet[cell->active_cell_index()]);
    if (it == by_tet.end()) continue;
    fe_force = 0;
    for (const LoadPoint* p : it->second) {
      const Point<3> xi =
          mapping.transform_real_to_unit_cell(cell, Point<3>(p->position.x(), p->position.y(), p->position.z()));
      for (unsigned i = 0; i < n; ++i) fe_force[i] += fe.shape_value(i, xi) * p->weight * force[component[i]];
    }
    cell->get_dof_indices(ids);
    zero_constraints.distribute_local_to_global(fe_force, ids, f);  // a force on a prescribed dof goes to the support
  }
  f.compress(VectorOperation::add);
}

void DistributedElasticity::Impl::solve_linear(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force) {
  auto clock = std::chrono::steady_clock::now();
  Vector f(lift);
  add_load(load, force, f);
  Vector x(u);
  stats.cg_iterations = cg(f, x, settings.cg_tolerance);
  stats.solve_s = lap(clock);
  constraints.distribute(x);
  u = x;
}

void DistributedElasticity::solve(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force) {
  if (impl_->settings.law == "linear")
    impl_->solve_linear(load, force);
  else
    impl_->solve_nonlinear(load, force);
}

Points DistributedElasticity::node_displacements(const std::vector<int>& nodes) const {
  const Impl& d = *impl_;
  std::unordered_map<int, Eigen::Index> row_of;
  for (size_t r = 0; r < nodes.size(); ++r) row_of.emplace(nodes[r], static_cast<Eigen::Index>(r));
  Points out = Points::Zero(static_cast<Eigen::Index>(nodes.size()), 3);
  // Each entry is written by the one rank owning its dof; the sum fills the rest.
  for (const auto& cell : d.dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    for (unsigned k = 0; k < 4; ++k) {
      const auto it = row_of.find(d.cell_nodes[cell->active_cell_index()][k]);
      if (it == row_of.end()) continue;
      for (unsigned c = 0; c < 3; ++c) {
        const types::global_dof_index dof = cell->vertex_dof_index(k, c);
        if (d.owned.is_element(dof)) out(it->second, c) = d.u[dof];
      }
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, out.data(), static_cast<int>(out.size()), MPI_DOUBLE, MPI_SUM, d.comm);
  return out;
}

}  // namespace tb
