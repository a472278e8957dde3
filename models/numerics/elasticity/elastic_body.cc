#include "elastic_body.h"

#include <algorithm>
#include <stdexcept>

#include "stiffness_assembly.h"

extern "C" void openblas_set_num_threads(int);  // libopenblas, linked explicitly
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

ElasticBody::ElasticBody(const TetMesh& mesh, const Material& material, const std::vector<char>& clamped)
    : mesh_(mesh), material_(material) {
  if (clamped.size() != static_cast<size_t>(mesh.V.rows()))
    throw std::invalid_argument("clamped flags: one per node expected");
  K_full_ = assemble_stiffness(mesh, material.youngs_modulus, material.poisson_ratio);
  const int ndof = static_cast<int>(3 * mesh.V.rows());
  full_to_free_.assign(static_cast<size_t>(ndof), -1);
  for (int d = 0; d < ndof; ++d)
    if (!clamped[static_cast<size_t>(d / 3)]) {
      full_to_free_[static_cast<size_t>(d)] = static_cast<int>(free_to_full_.size());
      free_to_full_.push_back(d);
    }
  if (free_to_full_.size() == static_cast<size_t>(ndof))
    throw std::invalid_argument("no node is clamped: the support selects nothing, so K is singular");
  if (free_to_full_.empty()) throw std::invalid_argument("every node is clamped: nothing can move");

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
