#include "elastic_solver.h"

#include <sstream>
#include <stdexcept>

#include "point_location.h"
#include "preconditioned_cg.h"
#include "stiffness_assembly.h"
#include "supernodal_cholesky.h"

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

struct ElasticSolver::Factorisation {
  Eigen::SparseMatrix<double> K_free;
  std::unique_ptr<SupernodalCholesky> cholesky;  // direct: factorised once
  SupernodalCholesky::SparseRhs rhs;             // the free dofs of the last load tet ...
  Eigen::Vector4i rhs_nodes;                     // ... whose nodes these are
  bool has_rhs = false;
  std::unique_ptr<PreconditionedCG> cg;  // iterative: warm-started each frame
};

namespace {
/// P: free dofs by coarse dofs, u_fine = P u_coarse by the P1 (barycentric)
/// interpolation of the coarse tet containing each fine node (the nearest tet,
/// extrapolated, for a node outside the coarse mesh). Coarse dofs that reach no
/// free dof are left out, so that P^T K P is nonsingular.
Eigen::SparseMatrix<double> coarse_prolongation(const TetMesh& fine, const TetMesh& coarse,
                                                const std::vector<int>& full_to_free, int free_dofs) {
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index v = 0; v < fine.V.rows(); ++v) {
    const TetEmbedding e = locate_point(coarse, fine.V.row(v).transpose());
    for (int c = 0; c < 3; ++c) {
      const int row = full_to_free[static_cast<size_t>(3 * v + c)];
      if (row < 0) continue;
      for (int k = 0; k < 4; ++k)
        if (e.weights(k) != 0) t.emplace_back(row, 3 * coarse.T(e.tet, k) + c, e.weights(k));
    }
  }
  Eigen::SparseMatrix<double> P(free_dofs, 3 * coarse.V.rows());
  P.setFromTriplets(t.begin(), t.end());
  std::vector<int> used_columns;
  for (Eigen::Index c = 0; c < P.cols(); ++c)
    if (P.col(c).nonZeros() > 0) used_columns.push_back(static_cast<int>(c));
  Eigen::SparseMatrix<double> Pu(P.rows(), static_cast<Eigen::Index>(used_columns.size()));
  for (size_t j = 0; j < used_columns.size(); ++j) Pu.col(static_cast<Eigen::Index>(j)) = P.col(used_columns[j]);
  Pu.makeCompressed();
  return Pu;
}
}  // namespace

ElasticSolver::ElasticSolver(const TetMesh& mesh, const Material& material, const std::vector<char>& clamped,
                             SolveMode mode, double cg_relative_tolerance, const TetMesh* coarse_space)
    : mesh_(mesh), mode_(mode), fact_(std::make_unique<Factorisation>()) {
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

  // K restricted to the free dofs (Dirichlet u = 0 on the clamped ones).
  std::vector<Eigen::Triplet<double>> t;
  for (int c = 0; c < K_full_.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K_full_, c); it; ++it) {
      const int r = full_to_free_[static_cast<size_t>(it.row())], cc = full_to_free_[static_cast<size_t>(it.col())];
      if (r >= 0 && cc >= 0) t.emplace_back(r, cc, it.value());
    }
  const auto n = static_cast<Eigen::Index>(free_to_full_.size());
  fact_->K_free.resize(n, n);
  fact_->K_free.setFromTriplets(t.begin(), t.end());
  if (mode_ == SolveMode::Direct)
    fact_->cholesky = std::make_unique<SupernodalCholesky>(fact_->K_free);
  else if (coarse_space) {
    const Eigen::SparseMatrix<double> P = coarse_prolongation(mesh, *coarse_space, full_to_free_, static_cast<int>(n));
    fact_->cg = std::make_unique<PreconditionedCG>(fact_->K_free, cg_relative_tolerance, 10 * static_cast<int>(n), &P);
  } else
    fact_->cg = std::make_unique<PreconditionedCG>(fact_->K_free, cg_relative_tolerance, 10 * static_cast<int>(n));
  f_free_ = Eigen::VectorXd::Zero(n);
  u_free_ = Eigen::VectorXd::Zero(n);
}

ElasticSolver::~ElasticSolver() = default;

double ElasticSolver::factor_nonzeros() const { return fact_->cholesky ? fact_->cholesky->factor_nonzeros() : 0; }

LoadStencil ElasticSolver::locate_load(const Eigen::Vector3d& point) const {
  const TetEmbedding e = locate_point(mesh_, point, 1e-6);
  if (e.tet < 0 || e.distance > 0) {
    std::ostringstream msg;
    msg << "load point (" << point.x() << ", " << point.y() << ", " << point.z() << ") is outside the mesh"
        << " (distance " << e.distance << " m)";
    throw std::invalid_argument(msg.str());
  }
  LoadStencil s;
  for (int k = 0; k < 4; ++k) s.nodes(k) = mesh_.T(e.tet, k);
  s.weights = e.weights;
  return s;
}

void ElasticSolver::solve(const LoadStencil& stencil, const Eigen::Vector3d& force, Eigen::VectorXd& u) {
  f_free_.setZero();
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < 3; ++c) {
      const int free = full_to_free_[static_cast<size_t>(3 * stencil.nodes(k) + c)];
      if (free >= 0) f_free_(free) += stencil.weights(k) * force(c);  // a force on a clamped node goes to the support
    }
  if (u.size() != 3 * mesh_.V.rows()) u = Eigen::VectorXd::Zero(3 * mesh_.V.rows());
  if (mode_ == SolveMode::Direct) {
    if (fact_->rhs_nodes != stencil.nodes || !fact_->has_rhs) {  // a new load tet: its forward-solve path
      std::vector<int> rows;
      for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 3; ++c) {
          const int free = full_to_free_[static_cast<size_t>(3 * stencil.nodes(k) + c)];
          if (free >= 0) rows.push_back(free);
        }
      fact_->rhs = fact_->cholesky->sparse_rhs(rows);
      fact_->rhs_nodes = stencil.nodes;
      fact_->has_rhs = true;
    }
    fact_->cholesky->solve(f_free_, fact_->rhs, u_free_);
    last_iterations_ = 0;
  } else {
    for (size_t i = 0; i < free_to_full_.size(); ++i) u_free_(static_cast<Eigen::Index>(i)) = u(free_to_full_[i]);
    last_iterations_ = fact_->cg->solve(f_free_, u_free_);
  }
  for (size_t i = 0; i < free_to_full_.size(); ++i) u(free_to_full_[i]) = u_free_(static_cast<Eigen::Index>(i));
}

}  // namespace tb
