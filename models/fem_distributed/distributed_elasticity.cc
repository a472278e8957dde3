// The distributed fine FEM, narrated:
//  1. Partition: every rank orders the tets along a Morton curve of their
//     centroids and takes one contiguous chunk (deterministic, the same on every
//     rank since every rank holds the same TetMesh).
//  2. Mesh: a parallel::fullydistributed::Triangulation from a description of the
//     rank's tets plus the ghost layer (tets sharing a node with them); a coarse
//     cell's id is its tet's index, which ties deal.II's cells to the TetMesh.
//  3. Dofs: FESystem(FE_SimplexP(degree), 3); a dof is clamped when its support
//     point (a node, or an edge midpoint for P2, computed exactly from the nodes)
//     is in the support, and held by a group (a tool) when its node is the group's
//     or (P2) it is the midpoint of a boundary edge whose two nodes are.
//  4. K from the element matrices of eq. (9) (elasticity_cell.h, the serial path's
//     own function), Trilinos CrsMatrix; AMG (ML smoothed aggregation) with the
//     rigid-body modes as near null space, built once. The groups' columns of K,
//     kept aside per group and component (group_lift), give the right-hand side of
//     any values of theirs: K_ff u_f = f_f - K_fp u_p.
//  5. Each solve: f from the load points (eq. 10 with the cell's shape functions)
//     and the body force rho g (int rho g N_i over the reference cells: a dead
//     load, the same integral as the serial consistent masses), CG warm-started
//     from the previous solution; then the reactions (the loads' share minus the
//     internal force at the constrained dofs).
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
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "distributed_elasticity_impl.h"
#include "volume_ordering.h"

namespace tb {
using namespace dealii;

namespace {

/// Owner rank of each tet: contiguous chunks of the tets in Morton order (morton_key,
/// volume_ordering.h).
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

/// The group holding each node's component c at 3 node + c (-1: none), the groups
/// checked. A node may be in several groups for different components (sliding
/// plates on two faces of an edge).
std::vector<int> node_groups(const TetMesh& m, const std::vector<PrescribedGroup>& groups) {
  std::vector<int> group(3 * static_cast<size_t>(m.V.rows()), -1);
  for (size_t g = 0; g < groups.size(); ++g) {
    const std::string name = "distributed FEM: prescribed group " + std::to_string(g);
    if (groups[g].nodes.empty()) throw std::invalid_argument(name + " has no node");
    if (!groups[g].components[0] && !groups[g].components[1] && !groups[g].components[2])
      throw std::invalid_argument(name + " holds no component");
    for (int n : groups[g].nodes) {
      if (n < 0 || n >= m.V.rows())
        throw std::invalid_argument(name + " names node " + std::to_string(n) + ", outside the mesh's " +
                                    std::to_string(m.V.rows()) + " nodes");
      for (int c = 0; c < 3; ++c) {
        if (!groups[g].components[c]) continue;
        int& owner = group[3 * static_cast<size_t>(n) + static_cast<size_t>(c)];
        if (owner >= 0 && owner != static_cast<int>(g))
          throw std::invalid_argument("distributed FEM: node " + std::to_string(n) + " is held by groups " +
                                      std::to_string(owner) + " and " + std::to_string(g) + " in component " +
                                      std::to_string(c));
        owner = static_cast<int>(g);
      }
    }
  }
  return group;
}

/// The edges of the boundary faces (tet faces that belong to one tet only) whose
/// two nodes one group holds in a component: {lower node, higher node, component}.
std::set<std::array<int, 3>> held_boundary_edges(const TetMesh& m, const std::vector<int>& group) {
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  auto held = [&](int a, int b, int c) {
    const int g = group[3 * static_cast<size_t>(a) + static_cast<size_t>(c)];
    return g >= 0 && g == group[3 * static_cast<size_t>(b) + static_cast<size_t>(c)];
  };
  auto any_held = [&](int a, int b) { return held(a, b, 0) || held(a, b, 1) || held(a, b, 2); };
  // Only faces with a held pair can give one; an interior face appears twice.
  std::vector<std::array<int, 3>> faces;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    for (const auto& f : kFace) {
      std::array<int, 3> n = {{m.T(t, f[0]), m.T(t, f[1]), m.T(t, f[2])}};
      if (!any_held(n[0], n[1]) && !any_held(n[0], n[2]) && !any_held(n[1], n[2])) continue;
      std::sort(n.begin(), n.end());
      faces.push_back(n);
    }
  std::sort(faces.begin(), faces.end());
  std::set<std::array<int, 3>> edges;
  for (size_t i = 0; i < faces.size();) {
    size_t j = i;
    while (j < faces.size() && faces[j] == faces[i]) ++j;
    if (j - i == 1)
      for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b)
          for (int c = 0; c < 3; ++c)
            if (held(faces[i][a], faces[i][b], c)) edges.insert(std::array<int, 3>{{faces[i][a], faces[i][b], c}});
    i = j;
  }
  return edges;
}

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
      density(m.density),
      law(&find_material_law(s.law)),
      tria(c),
      fe(FE_SimplexP<3>(static_cast<unsigned>(s.degree)), 3),
      mapping(FE_SimplexP<3>(1)),
      quadrature(static_cast<unsigned>(s.degree)) {}

DistributedElasticity::DistributedElasticity(const TetMesh& mesh, const Material& material, const Predicate& support,
                                             const DistributedSettings& settings, MPI_Comm comm,
                                             const Field& prescribed, const std::vector<PrescribedGroup>& groups) {
  if (settings.degree != 1 && settings.degree != 2)
    throw std::invalid_argument("distributed FEM: degree " + std::to_string(settings.degree) +
                                " is not supported (1: P1, 2: P2)");
  if (prescribed && settings.law != "linear")
    throw std::invalid_argument("distributed FEM: prescribed displacements need the linear law");
  const std::vector<int> node_group = node_groups(mesh, groups);
  impl_ = std::make_unique<Impl>(comm, settings, material);
  Impl& d = *impl_;
  d.groups = groups;
  d.group_values.assign(groups.size(), Eigen::Vector3d::Zero());
  d.reactions.assign(groups.size() + 1, Eigen::Vector3d::Zero());
  d.n_tets = mesh.T.rows();
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
  // A group's P2 midside dofs: on the boundary edges both of whose nodes it holds
  // (distributed_elasticity.h says why).
  const std::set<std::array<int, 3>> held_edges =
      groups.empty() || settings.degree == 1 ? std::set<std::array<int, 3>>() : held_boundary_edges(mesh, node_group);
  std::vector<types::global_dof_index> ids(n);
  long long supported_here = 0, held_here = 0;
  std::vector<long long> clamped_and_held(groups.size(), 0), held_by_group(groups.size(), 0);
  for (const auto& cell : d.dof_handler.active_cell_iterators()) {
    if (cell->is_artificial()) continue;
    // The TetMesh nodes of the cell's vertices, matched by position.
    const int tet = static_cast<int>(cell->id().get_coarse_cell_id());
    d.cell_tet[cell->active_cell_index()] = tet;
    std::array<int, 4>& nodes = d.cell_nodes[cell->active_cell_index()];
    for (unsigned k = 0; k < 4; ++k) {
      int node = -1;
      for (int j = 0; j < 4; ++j)
        if (mesh.V.row(mesh.T(tet, j)).transpose() == to_eigen(cell->vertex(k))) node = mesh.T(tet, j);
      if (node < 0) throw std::logic_error("distributed FEM: a cell's vertex is not a node of its tet");
      nodes[k] = node;
    }
    cell->get_dof_indices(ids);
    for (unsigned i = 0; i < n; ++i) {
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (unsigned k = 0; k < 4; ++k) x += lambda[i][k] * to_eigen(cell->vertex(k));
      const bool owned = d.owned.is_element(ids[i]);
      if (owned) {
        d.owned_support_points[d.owned.index_within_set(ids[i])] = x;
        d.owned_components[d.owned.index_within_set(ids[i])] = d.component[i];
      }
      if (d.constraints.is_constrained(ids[i])) continue;
      // Its group: the node's in its component (a vertex dof), or the edge's when
      // one group holds both its nodes in that component and it is a boundary edge
      // (a P2 midside dof: unit support point barycentrics 1/2, 1/2).
      const int c = static_cast<int>(d.component[i]);
      int group = -1;
      std::array<int, 2> at{{-1, -1}};
      int count = 0;
      for (unsigned k = 0; k < 4; ++k)
        if (lambda[i][k] > 0.25 && count < 2) at[static_cast<size_t>(count++)] = nodes[k];
      if (count == 1) {
        group = node_group[3 * static_cast<size_t>(at[0]) + static_cast<size_t>(c)];
      } else if (count == 2 &&
                 held_edges.count(std::array<int, 3>{{std::min(at[0], at[1]), std::max(at[0], at[1]), c}})) {
        group = node_group[3 * static_cast<size_t>(at[0]) + static_cast<size_t>(c)];
      }
      const bool clamped = support(x);
      if (group < 0 && !clamped) continue;
      d.constraints.add_line(ids[i]);
      d.zero_constraints.add_line(ids[i]);
      if (group >= 0 && clamped) {
        clamped_and_held[static_cast<size_t>(group)] += owned;
        continue;  // an error below, on every rank
      }
      if (group >= 0) {
        d.held_relevant.push_back({ids[i], group, d.component[i]});
        d.group_of_dof.emplace(ids[i], group);
        if (owned) d.held_owned.push_back({ids[i], group, d.component[i]});
        held_here += owned;
        held_by_group[static_cast<size_t>(group)] += owned;
      } else {
        if (prescribed) d.constraints.set_inhomogeneity(ids[i], prescribed(x)[d.component[i]]);
        supported_here += owned;
      }
    }
  }
  d.constraints.close();
  d.zero_constraints.close();
  // Global counts, the same on every rank (so are the errors below).
  std::vector<long long> counts = {supported_here, held_here};
  counts.insert(counts.end(), clamped_and_held.begin(), clamped_and_held.end());
  counts.insert(counts.end(), held_by_group.begin(), held_by_group.end());
  MPI_Allreduce(MPI_IN_PLACE, counts.data(), static_cast<int>(counts.size()), MPI_LONG_LONG, MPI_SUM, comm);
  d.stats.supported_dofs = counts[0];
  d.stats.held_dofs = counts[1];
  std::copy(counts.begin() + 2, counts.begin() + 2 + static_cast<long>(groups.size()), clamped_and_held.begin());
  std::copy(counts.begin() + 2 + static_cast<long>(groups.size()), counts.end(), held_by_group.begin());
  for (size_t g = 0; g < groups.size(); ++g) {
    if (clamped_and_held[g] > 0)
      throw std::invalid_argument("distributed FEM: prescribed group " + std::to_string(g) + " holds " +
                                  std::to_string(clamped_and_held[g]) +
                                  " dofs the support clamps: a dof cannot be clamped and moved");
    if (held_by_group[g] == 0)
      throw std::invalid_argument("distributed FEM: prescribed group " + std::to_string(g) + " holds no dof");
  }
  if (d.stats.supported_dofs + d.stats.held_dofs == 0)
    throw std::invalid_argument("distributed FEM: the support selects no dof and no group holds one, so K is singular");
  // The owned cells with a constrained dof: where the reactions are measured.
  for (const auto& cell : d.dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    cell->get_dof_indices(ids);
    for (unsigned i = 0; i < n; ++i)
      if (d.zero_constraints.is_constrained(ids[i])) {
        d.constrained_cells.push_back(cell);
        break;
      }
  }

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
    d.group_lift.resize(3 * groups.size());
    for (Impl::Vector& v : d.group_lift) v.reinit(d.owned, comm);
    std::vector<types::global_dof_index> rows;
    std::vector<double> values;
    for (const auto& cell : d.dof_handler.active_cell_iterators()) {
      if (!cell->is_locally_owned()) continue;
      fe_values.reinit(cell);
      linear_elastic_cell_matrix(fe_values, d.component, LinearElastic(d.lame), Ke, grad);  // eq. (9)
      cell->get_dof_indices(ids);
      d.constraints.distribute_local_to_global(Ke, no_force, ids, d.K, d.lift);  // lift: -K g of prescribed g
      // Each held column j: -K_ij on the free rows i, into its group and component's lift.
      for (unsigned j = 0; j < n; ++j) {
        if (!d.zero_constraints.is_constrained(ids[j])) continue;
        const auto it = d.group_of_dof.find(ids[j]);
        if (it == d.group_of_dof.end()) continue;
        rows.clear();
        values.clear();
        for (unsigned i = 0; i < n; ++i)
          if (!d.zero_constraints.is_constrained(ids[i])) {
            rows.push_back(ids[i]);
            values.push_back(-Ke(i, j));
          }
        if (!rows.empty()) d.group_lift[3 * static_cast<size_t>(it->second) + d.component[j]].add(rows, values);
      }
    }
    d.K.compress(VectorOperation::add);
    d.lift.compress(VectorOperation::add);
    for (Impl::Vector& v : d.group_lift) v.compress(VectorOperation::add);
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

void DistributedElasticity::Impl::cell_load(const Cell& cell, const std::vector<const LoadPoint*>& points,
                                            const Eigen::Vector3d& force, dealii::Vector<double>& fe_force) const {
  const unsigned n = fe.n_dofs_per_cell();
  fe_force.reinit(n);
  for (const LoadPoint* p : points) {
    const Point<3> xi =
        mapping.transform_real_to_unit_cell(cell, Point<3>(p->position.x(), p->position.y(), p->position.z()));
    for (unsigned i = 0; i < n; ++i) fe_force[i] += fe.shape_value(i, xi) * p->weight * force[component[i]];
  }
}

namespace {
std::unordered_map<int, std::vector<const LoadPoint*>> points_by_tet(const std::vector<LoadPoint>& load) {
  std::unordered_map<int, std::vector<const LoadPoint*>> by_tet;
  for (const LoadPoint& p : load) by_tet[p.at.tet].push_back(&p);
  return by_tet;
}
}  // namespace

void DistributedElasticity::Impl::add_load(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force,
                                           Vector& f) const {
  const unsigned n = fe.n_dofs_per_cell();
  dealii::Vector<double> fe_force(n);
  std::vector<types::global_dof_index> ids(n);
  const auto by_tet = points_by_tet(load);
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    const auto it = by_tet.find(cell_tet[cell->active_cell_index()]);
    if (it == by_tet.end()) continue;
    cell_load(cell, it->second, force, fe_force);
    cell->get_dof_indices(ids);
    zero_constraints.distribute_local_to_global(fe_force, ids,
                                                f);  // a force on a constrained dof goes to the support or tool
  }
  f.compress(VectorOperation::add);
}

void DistributedElasticity::Impl::add_body_force(const Eigen::Vector3d& g, Vector& f) {
  if (g.isZero()) return;
  if (body_unit.empty()) {
    const unsigned n = fe.n_dofs_per_cell();
    FEValues<3> fe_values(mapping, fe, quadrature, update_values | update_JxW_values);
    dealii::Vector<double> fe_force(n);
    std::vector<types::global_dof_index> ids(n);
    body_unit.assign(3, Vector(owned, comm));
    for (const auto& cell : dof_handler.active_cell_iterators()) {
      if (!cell->is_locally_owned()) continue;
      fe_values.reinit(cell);
      cell->get_dof_indices(ids);
      for (unsigned c = 0; c < 3; ++c) {
        body_force_cell(fe_values, component, density * Eigen::Vector3d::Unit(static_cast<Eigen::Index>(c)), fe_force);
        zero_constraints.distribute_local_to_global(fe_force, ids, body_unit[c]);  // as add_load
      }
    }
    for (Vector& v : body_unit) v.compress(VectorOperation::add);
  }
  for (unsigned c = 0; c < 3; ++c)
    if (g[c] != 0) f.add(g[c], body_unit[c]);
}

DistributedElasticity::Impl::Vector DistributedElasticity::Impl::ghosted(const Vector& owned_vector) const {
  Vector g(owned, relevant, comm);
  g = owned_vector;
  return g;
}

void DistributedElasticity::Impl::set_held(Vector& x, const std::vector<Eigen::Vector3d>* values) const {
  for (const HeldDof& h : held_owned) x[h.dof] = values ? (*values)[static_cast<size_t>(h.group)][h.component] : 0.0;
  x.compress(VectorOperation::insert);
}

void DistributedElasticity::Impl::solve_linear(const Vector& f_external, const std::vector<Eigen::Vector3d>& values) {
  auto clock = std::chrono::steady_clock::now();
  Vector f(lift);
  // K_ff u_f = f_f - K_fp u_p: each held component's value times its column sum.
  for (size_t g = 0; g < groups.size(); ++g)
    for (unsigned c = 0; c < 3; ++c)
      if (groups[g].components[c] && values[g][c] != 0) f.add(values[g][c], group_lift[3 * g + c]);
  f += f_external;
  Vector x(u);
  set_held(x, nullptr);  // a held dof's row is decoupled, with right-hand side 0
  stats.cg_iterations = cg(f, x, settings.cg_tolerance);
  stats.solve_s = lap(clock);
  constraints.distribute(x);
  set_held(x, &values);
  u = x;
}

void DistributedElasticity::Impl::measure_reactions(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force,
                                                    const Eigen::Vector3d& g) {
  const unsigned n = fe.n_dofs_per_cell();
  const size_t support = groups.size();  // the support's slot, after the groups'
  std::vector<double> sums(3 * (support + 1), 0.0);
  const Vector u_ghosted = ghosted(u);
  const auto by_tet = points_by_tet(load);
  FEValues<3> fe_values(mapping, fe, quadrature, update_values | update_gradients | update_JxW_values);
  FullMatrix<double> Ke;
  dealii::Vector<double> u_cell(n), Re(n), fe_force(n), fe_body(n);
  std::vector<Tensor<1, 3>> grad;
  std::vector<types::global_dof_index> ids(n);
  const bool linear = settings.law == "linear";
  for (const Cell& cell : constrained_cells) {
    fe_values.reinit(cell);
    cell->get_dof_values(u_ghosted, u_cell);
    cell->get_dof_indices(ids);
    // The internal force: K^e u^e (eq. 9), or the law's (elasticity_cell.h), defined
    // at a converged state.
    if (linear) {
      linear_elastic_cell_matrix(fe_values, component, LinearElastic(lame), Ke, grad);
      Ke.vmult(Re, u_cell);
    } else if (!hyperelastic_cell(fe_values, component, u_cell, *law, lame, nullptr, Re, grad)) {
      throw std::logic_error("distributed FEM: the converged state has J <= 0 in a cell");
    }
    const auto it = by_tet.find(cell_tet[cell->active_cell_index()]);
    if (it != by_tet.end())
      cell_load(cell, it->second, force, fe_force);
    else
      fe_force = 0;
    if (!g.isZero()) {
      body_force_cell(fe_values, component, density * g, fe_body);
      fe_force += fe_body;
    }
    for (unsigned i = 0; i < n; ++i) {
      if (!zero_constraints.is_constrained(ids[i])) continue;
      const auto held = group_of_dof.find(ids[i]);
      const size_t slot = held == group_of_dof.end() ? support : static_cast<size_t>(held->second);
      sums[3 * slot + component[i]] += fe_force[i] - Re[i];
    }
  }
  // Each cell is one rank's: the sum over ranks counts it once.
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM, comm);
  for (size_t k = 0; k <= support; ++k) reactions[k] = Eigen::Vector3d(sums[3 * k], sums[3 * k + 1], sums[3 * k + 2]);
}

void DistributedElasticity::solve(const std::vector<LoadPoint>& load, const Eigen::Vector3d& force,
                                  const std::vector<Eigen::Vector3d>& group_values, const Eigen::Vector3d& gravity) {
  Impl& d = *impl_;
  if (group_values.size() != d.groups.size())
    throw std::invalid_argument("distributed FEM: " + std::to_string(group_values.size()) + " group values for " +
                                std::to_string(d.groups.size()) + " prescribed groups");
  if (!gravity.allFinite()) throw std::invalid_argument("distributed FEM: the body force's acceleration is not finite");
  if (!gravity.isZero() && !(d.density > 0)) {
    std::ostringstream msg;
    msg << "distributed FEM: a body force needs a positive density, not " << d.density;
    throw std::invalid_argument(msg.str());
  }
  Impl::Vector f(d.owned, d.comm);
  d.add_load(load, force, f);
  d.add_body_force(gravity, f);
  if (d.settings.law == "linear")
    d.solve_linear(f, group_values);
  else
    d.solve_nonlinear(f, group_values);
  d.group_values = group_values;
  d.measure_reactions(load, force, gravity);
}

const std::vector<Eigen::Vector3d>& DistributedElasticity::reactions() const { return impl_->reactions; }

void DistributedElasticity::set_probes(const Points& points, const std::vector<int>& tets) {
  Impl& d = *impl_;
  if (static_cast<size_t>(points.rows()) != tets.size())
    throw std::invalid_argument("distributed FEM: " + std::to_string(points.rows()) + " probes and " +
                                std::to_string(tets.size()) + " tets");
  std::unordered_map<int, Impl::Cell> owned_cell;
  for (const auto& cell : d.dof_handler.active_cell_iterators())
    if (cell->is_locally_owned()) owned_cell.emplace(d.cell_tet[cell->active_cell_index()], cell);
  const unsigned n = d.fe.n_dofs_per_cell();
  d.probes.clear();
  for (Eigen::Index p = 0; p < points.rows(); ++p) {
    const int tet = tets[static_cast<size_t>(p)];
    if (tet < 0 || tet >= d.n_tets)
      throw std::invalid_argument("distributed FEM: probe " + std::to_string(p) + " names tet " + std::to_string(tet) +
                                  ", outside the mesh's " + std::to_string(d.n_tets) + " tets");
    const auto it = owned_cell.find(tet);
    if (it == owned_cell.end()) continue;  // another rank's
    const Point<3> xi =
        d.mapping.transform_real_to_unit_cell(it->second, Point<3>(points(p, 0), points(p, 1), points(p, 2)));
    Impl::OwnedProbe probe{p, it->second, std::vector<double>(n)};
    for (unsigned i = 0; i < n; ++i) probe.shape[i] = d.fe.shape_value(i, xi);
    d.probes.push_back(std::move(probe));
  }
  d.probe_count = points.rows();
}

Points DistributedElasticity::probe_displacements() const {
  const Impl& d = *impl_;
  Points out = Points::Zero(d.probe_count, 3);
  const Impl::Vector u_ghosted = d.ghosted(d.u);
  dealii::Vector<double> u_cell(d.fe.n_dofs_per_cell());
  for (const Impl::OwnedProbe& p : d.probes) {
    p.cell->get_dof_values(u_ghosted, u_cell);
    for (unsigned i = 0; i < u_cell.size(); ++i) out(p.row, d.component[i]) += p.shape[i] * u_cell[i];
  }
  // Each probe is in one rank's cell: the sum is its value.
  MPI_Allreduce(MPI_IN_PLACE, out.data(), static_cast<int>(out.size()), MPI_DOUBLE, MPI_SUM, d.comm);
  return out;
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
