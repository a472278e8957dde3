#include "elastic_body.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

#include "elastic_solve.h"
#include "stiffness_assembly.h"

extern "C" void openblas_set_num_threads(int);  // libopenblas, linked explicitly
extern "C" int openblas_get_num_threads();
extern "C" void omp_set_num_threads(int);       // libgomp, via CHOLMOD
extern "C" void omp_set_max_active_levels(int);

namespace tb {

void use_one_thread() {
  openblas_set_num_threads(1);
  omp_set_num_threads(1);
  // CHOLMOD's supernodal factorisation asks for num_threads(4) explicitly, which
  // omp_set_num_threads does not cap; no active parallel level does.
  omp_set_max_active_levels(0);
  limit_assembly_threads(1);
}

BlasThreads::BlasThreads(int threads) : previous_(openblas_get_num_threads()), threads_(threads) {
  if (threads_ != previous_) openblas_set_num_threads(threads_);
}
BlasThreads::~BlasThreads() {
  if (threads_ != previous_) openblas_set_num_threads(previous_);
}

ElasticBody::ElasticBody(const TetMesh& mesh, const Material& material, const std::vector<char>& clamped,
                         std::vector<PrescribedGroup> prescribed, const std::vector<NodeSpring>& springs)
    : mesh_(mesh), material_(material), groups_(std::move(prescribed)) {
  if (clamped.size() != static_cast<size_t>(mesh.V.rows()))
    throw std::invalid_argument("clamped flags: one per node expected");
  K_full_ = assemble_stiffness(mesh, material.youngs_modulus, material.poisson_ratio);
  const int ndof = static_cast<int>(3 * mesh.V.rows());
  // Each dof's group, -1 if none.
  std::vector<int> group_of(static_cast<size_t>(ndof), -1);
  for (size_t g = 0; g < groups_.size(); ++g) {
    if (groups_[g].nodes.empty()) throw std::invalid_argument("prescribed group " + std::to_string(g) + " has no node");
    for (int n : groups_[g].nodes) {
      if (n < 0 || n >= mesh.V.rows() || clamped[static_cast<size_t>(n)])
        throw std::invalid_argument("prescribed group " + std::to_string(g) + ": node " + std::to_string(n) +
                                    (n < 0 || n >= mesh.V.rows() ? " is not a node of the mesh" : " is clamped"));
      for (int c = 0; c < 3; ++c) {
        if (!groups_[g].components[c]) continue;
        int& owner = group_of[static_cast<size_t>(3 * n + c)];
        if (owner >= 0)
          throw std::invalid_argument("node " + std::to_string(n) + " is prescribed by groups " +
                                      std::to_string(owner) + " and " + std::to_string(g));
        owner = static_cast<int>(g);
      }
    }
  }
  full_to_free_.assign(static_cast<size_t>(ndof), -1);
  for (int d = 0; d < ndof; ++d) {
    if (clamped[static_cast<size_t>(d / 3)]) {
      clamped_dof_.push_back(d);
    } else if (group_of[static_cast<size_t>(d)] >= 0) {
      prescribed_dof_.push_back(d);
      prescribed_group_.push_back(group_of[static_cast<size_t>(d)]);
    } else {
      full_to_free_[static_cast<size_t>(d)] = static_cast<int>(free_to_full_.size());
      free_to_full_.push_back(d);
    }
  }
  if (clamped_dof_.empty() && prescribed_dof_.empty())
    throw std::invalid_argument("no node is clamped: the support selects nothing, so K is singular");
  if (free_to_full_.empty()) throw std::invalid_argument("every node is clamped or prescribed: nothing can move");
  if (!springs.empty()) {
    spring_stiffness_ = Eigen::VectorXd::Zero(mesh.V.rows());
    for (const NodeSpring& s : springs) {
      if (s.node < 0 || s.node >= mesh.V.rows())
        throw std::invalid_argument("spring: node " + std::to_string(s.node) + " is not a node of the mesh");
      if (!(std::isfinite(s.stiffness) && s.stiffness > 0))
        throw std::invalid_argument("spring at node " + std::to_string(s.node) + ": stiffness " +
                                    std::to_string(s.stiffness) + " N/m is not positive and finite");
      for (int c = 0; c < 3; ++c)
        if (free_index(3 * s.node + c) < 0)
          throw std::invalid_argument("spring at node " + std::to_string(s.node) +
                                      ": the node is clamped or prescribed (a spring pulls a free node)");
      spring_stiffness_(s.node) += s.stiffness;
    }
    for (Eigen::Index v = 0; v < mesh.V.rows(); ++v)
      for (int c = 0; c < 3; ++c)
        if (spring_stiffness_(v) != 0) K_full_.coeffRef(3 * v + c, 3 * v + c) += spring_stiffness_(v);
  }

  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(K_full_.nonZeros()));
  for (int c = 0; c < K_full_.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K_full_, c); it; ++it) {
      const int r = free_index(static_cast<int>(it.row())), cc = free_index(static_cast<int>(it.col()));
      if (r >= 0 && cc >= 0) t.emplace_back(r, cc, it.value());
    }
  const auto n = static_cast<Eigen::Index>(free_to_full_.size());
  K_free_.resize(n, n);
  K_free_.setFromTriplets(t.begin(), t.end());

  // K_fp: free rows by prescribed dofs (K is symmetric: column p of K holds row p).
  std::vector<Eigen::Triplet<double>> fp;
  for (size_t k = 0; k < prescribed_dof_.size(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K_full_, prescribed_dof_[k]); it; ++it) {
      const int r = free_index(static_cast<int>(it.row()));
      if (r >= 0 && it.value() != 0) {
        fp.emplace_back(r, static_cast<int>(k), it.value());
        coupled_rows_.push_back(r);
      }
    }
  K_fp_.resize(n, static_cast<Eigen::Index>(prescribed_dof_.size()));
  K_fp_.setFromTriplets(fp.begin(), fp.end());
  std::sort(coupled_rows_.begin(), coupled_rows_.end());
  coupled_rows_.erase(std::unique(coupled_rows_.begin(), coupled_rows_.end()), coupled_rows_.end());
  u_p_.setZero(static_cast<Eigen::Index>(prescribed_dof_.size()));
}

void ElasticBody::subtract_prescribed(const std::vector<Eigen::Vector3d>& group_values,
                                      Eigen::VectorXd& f_free) const {
  if (groups_.empty()) return;
  if (group_values.size() != groups_.size())
    throw std::invalid_argument("prescribed values: " + std::to_string(group_values.size()) + " for " +
                                std::to_string(groups_.size()) + " groups");
  for (size_t k = 0; k < prescribed_dof_.size(); ++k)
    u_p_(static_cast<Eigen::Index>(k)) = group_values[static_cast<size_t>(prescribed_group_[k])](prescribed_dof_[k] % 3);
  f_free.noalias() -= K_fp_ * u_p_;
}

void ElasticBody::set_prescribed(const std::vector<Eigen::Vector3d>& group_values, Eigen::VectorXd& u) const {
  if (groups_.empty()) return;
  if (u.size() != dofs()) u = Eigen::VectorXd::Zero(dofs());
  for (size_t k = 0; k < prescribed_dof_.size(); ++k)
    u(prescribed_dof_[k]) = group_values[static_cast<size_t>(prescribed_group_[k])](prescribed_dof_[k] % 3);
}

void ElasticBody::reactions(const Eigen::VectorXd& u, const Eigen::VectorXd& f, std::vector<Eigen::Vector3d>& groups,
                            Eigen::Vector3d& support, const Eigen::VectorXd* internal_force) const {
  groups.resize(groups_.size());
  for (Eigen::Vector3d& g : groups) g.setZero();
  support.setZero();
  // (K u)_c = column c of K (symmetric) dotted with u.
  const auto force_at = [&](int c) { return f(c) - (internal_force ? (*internal_force)(c) : K_full_.col(c).dot(u)); };
  for (size_t k = 0; k < prescribed_dof_.size(); ++k)
    groups[static_cast<size_t>(prescribed_group_[k])](prescribed_dof_[k] % 3) += force_at(prescribed_dof_[k]);
  for (int c : clamped_dof_) support(c % 3) += force_at(c);
}

void ElasticBody::to_free(const Eigen::VectorXd& u, Eigen::VectorXd& u_free) const {
  if (u_free.size() != free_dofs()) u_free.resize(free_dofs());
  for (size_t i = 0; i < free_to_full_.size(); ++i) u_free(static_cast<Eigen::Index>(i)) = u(free_to_full_[i]);
}

void ElasticBody::to_full(const Eigen::VectorXd& u_free, Eigen::VectorXd& u) const {
  if (u.size() != dofs()) u = Eigen::VectorXd::Zero(dofs());
  for (size_t i = 0; i < free_to_full_.size(); ++i) u(free_to_full_[i]) = u_free(static_cast<Eigen::Index>(i));
}

BodyLoads::BodyLoads(const ElasticBody& body, std::vector<NodalWeights> per_load)
    : body_(body), per_load_(std::move(per_load)) {
  for (const NodalWeights& w : per_load_)
    for (Eigen::Index k = 0; k < w.size(); ++k) {
      if (w.nodes(k) < 0 || w.nodes(k) >= body.mesh().V.rows())
        throw std::invalid_argument("load on node " + std::to_string(w.nodes(k)) + ", outside the mesh's " +
                                    std::to_string(body.mesh().V.rows()) + " nodes");
      for (int c = 0; c < 3; ++c) {
        const int free = body.free_index(3 * w.nodes(k) + c);
        if (free >= 0) loaded_free_dofs_.push_back(free);
      }
    }
  std::sort(loaded_free_dofs_.begin(), loaded_free_dofs_.end());
  loaded_free_dofs_.erase(std::unique(loaded_free_dofs_.begin(), loaded_free_dofs_.end()), loaded_free_dofs_.end());
}

void BodyLoads::assemble_full(const std::vector<Eigen::Vector3d>& values, Eigen::VectorXd& f) const {
  if (values.size() != per_load_.size())
    throw std::invalid_argument("body loads: " + std::to_string(values.size()) + " values for " +
                                std::to_string(per_load_.size()) + " loads");
  if (f.size() != body_.dofs()) f.resize(body_.dofs());
  f.setZero();
  for (size_t l = 0; l < per_load_.size(); ++l) {
    const NodalWeights& w = per_load_[l];
    for (Eigen::Index k = 0; k < w.size(); ++k) f.segment<3>(3 * w.nodes(k)) += w.weights(k) * values[l];
  }
}

void BodyLoads::assemble(const std::vector<Eigen::Vector3d>& values, Eigen::VectorXd& f_free) const {
  if (values.size() != per_load_.size())
    throw std::invalid_argument("body loads: " + std::to_string(values.size()) + " values for " +
                                std::to_string(per_load_.size()) + " loads");
  if (f_free.size() != body_.free_dofs()) f_free.resize(body_.free_dofs());
  f_free.setZero();
  for (size_t l = 0; l < per_load_.size(); ++l) {
    const NodalWeights& w = per_load_[l];
    for (Eigen::Index k = 0; k < w.size(); ++k)
      for (int c = 0; c < 3; ++c) {
        const int free = body_.free_index(3 * w.nodes(k) + c);
        if (free >= 0) f_free(free) += w.weights(k) * values[l](c);
      }
  }
}

}  // namespace tb

namespace tb {

void unit_translation_response(const ElasticBody& body, ElasticSolve& solve, size_t g, int c, Eigen::VectorXd& u) {
  std::vector<Eigen::Vector3d> unit(body.prescribed_groups().size(), Eigen::Vector3d::Zero());
  unit.at(g) = Eigen::Vector3d::Unit(c);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(body.free_dofs());
  body.subtract_prescribed(unit, f);
  u.setZero(body.dofs());
  solve.solve(f, &body.prescribed_coupled_rows(), u);
  body.set_prescribed(unit, u);
}

ElasticFrame::ElasticFrame(const ElasticBody& body, const BodyLoads& loads, ElasticSolve& solve)
    : body_(body), loads_(loads), solve_(solve) {
  const size_t groups = body.prescribed_groups().size();
  group_forces_.assign(groups, Eigen::Vector3d::Zero());
  if (solve.factorised() && groups > 0) {
    rows_ = loads.loaded_free_dofs();
    Eigen::VectorXd u;
    for (size_t g = 0; g < groups; ++g) {
      group_response_.push_back(Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(body.free_dofs(), 3));
      for (int c = 0; c < 3; ++c) {
        if (!body.prescribed_groups()[g].components[c]) continue;
        unit_translation_response(body, solve, g, c, u);
        body.to_free(u, u_free_);
        group_response_.back().col(c) = u_free_;
      }
    }
    return;
  }
  std::set_union(loads.loaded_free_dofs().begin(), loads.loaded_free_dofs().end(),
                 body.prescribed_coupled_rows().begin(), body.prescribed_coupled_rows().end(),
                 std::back_inserter(rows_));
}

void ElasticFrame::step(const std::vector<Eigen::Vector3d>& load_values,
                        const std::vector<Eigen::Vector3d>& group_values, Eigen::VectorXd& u) {
  loads_.assemble(load_values, f_free_);
  const bool precomputed = !group_response_.empty();
  if (solve_.linear() && !precomputed) body_.subtract_prescribed(group_values, f_free_);
  body_.set_prescribed(group_values, u);  // before the solve: a strategy may read u whole
  if (!precomputed) {
    solve_.solve(f_free_, &rows_, u);
  } else {  // u_f = K_ff^-1 f_f + sum_g W_g d_g
    if (rows_.empty()) {  // no load reaches a free dof: only the tools move the body
      u_free_.setZero(body_.free_dofs());
    } else {
      solve_.solve(f_free_, &rows_, u);
      body_.to_free(u, u_free_);
    }
    for (size_t g = 0; g < group_response_.size(); ++g) u_free_.noalias() += group_response_[g] * group_values[g];
    body_.to_full(u_free_, u);
  }
  body_.set_prescribed(group_values, u);
  loads_.assemble_full(load_values, f_full_);
  body_.reactions(u, f_full_, group_forces_, support_force_, solve_.internal_force());
}

}  // namespace tb
