// How K u = f (eq. 11) is solved each frame on an assembled ElasticBody: a
// strategy chosen by parameter, so the fine FEM and the hybrid's coarse mesh pick
// theirs without either model knowing how it works. The strategies are listed
// once, in elastic_solve.cc; adding one is one class and one line there.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "elastic_body.h"
#include "parameters.h"

namespace tb {

class ElasticSolve {
 public:
  virtual ~ElasticSolve() = default;
  /// This frame's displacement under `force` applied through `load`.
  ///   u  3 #V: in, the previous frame's (a warm start, or the state a nonlinear
  ///      strategy continues from); out, this frame's. Sized on first use.
  /// No heap allocation once the load's nodes have been seen.
  virtual void solve(const LoadStencil& load, const Eigen::Vector3d& force, Eigen::VectorXd& u) = 0;
  /// Solver iterations of the last solve, where meaningful (else 0).
  virtual int last_iterations() const { return 0; }
  /// Facts worth writing beside a result (factor size, preconditioner ...).
  virtual nlohmann::json report() const { return nlohmann::json::object(); }
};

/// What a strategy may need beyond the body.
struct ElasticSolveOptions {
  double cg_tolerance = 1e-8;         ///< iterative: relative residual
  std::string preconditioner = "ic";  ///< iterative: "ic" or "two_level"
  /// iterative, two_level: a coarser tet mesh of the same body whose P1
  /// interpolation is the coarse space (nullptr: two_level is an error)
  const TetMesh* coarse_space = nullptr;
  /// corotational: "converged" (rotation updates and solves until the rotations
  /// no longer change the solution, at most corotational_max_updates) or
  /// "per_frame" (one update and one linearised solve per call)
  std::string corotational_update = "converged";
  int corotational_max_updates = 1000;
  /// corotational: the fraction of each update's solve step taken, in (0, 1]
  double corotational_relaxation = 0.5;
};

struct ElasticSolveInfo {
  std::string name;
  std::string description;
  std::function<std::unique_ptr<ElasticSolve>(const ElasticBody&, const ElasticSolveOptions&)> create;
};

/// Every strategy, in one explicit list.
const std::vector<ElasticSolveInfo>& elastic_solves();

/// The strategy called `name` on `body` (which must outlive it). Throws
/// std::invalid_argument for an unknown name or unusable options.
std::unique_ptr<ElasticSolve> make_elastic_solve(const std::string& name, const ElasticBody& body,
                                                 const ElasticSolveOptions& options);

/// The model parameters that choose and tune an elastic solve, each name prefixed
/// by `prefix` ("" in the fem model: solver, preconditioner, cg_tolerance;
/// "coarse_" in the hybrid): declared once here for every model that has one.
std::vector<ParameterSpec> elastic_solve_parameters(const std::string& prefix, const std::string& default_solver,
                                                    const std::string& default_preconditioner);

/// The strategy the resolved parameters `p` ask for (names with `prefix`).
std::unique_ptr<ElasticSolve> make_elastic_solve(const ElasticBody& body, const Parameters& p,
                                                 const std::string& prefix, const TetMesh* coarse_space);

}  // namespace tb
