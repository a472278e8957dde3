// How K u = f (eq. 11) is solved each frame on an assembled ElasticBody: a
// strategy chosen by parameter, so the fine FEM and the coarse meshes of the
// hybrid and embedded models pick theirs without knowing how it works. Each
// strategy is one file (direct_solve.cc, iterative_solve.cc, corotational_solve.cc)
// declaring its own parameters; the list of strategies is elastic_solve.cc, one
// line each (docs/extending.md).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <stdexcept>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "elastic_body.h"
#include "parameters.h"
#include "sphere_obstacles.h"

namespace tb {

class ElasticSolve {
 public:
  virtual ~ElasticSolve() = default;
  /// This frame's displacement under the force f_free on the body's free dofs.
  ///   f_free        #free dofs
  ///   nonzero_rows  the free dofs where f_free may be nonzero, sorted (null:
  ///                 anywhere); a strategy may use them (direct: the forward
  ///                 substitution visits only their elimination-tree paths)
  ///   u             3 #V: in, the previous frame's (a warm start, or the state a
  ///                 nonlinear strategy continues from); out, this frame's.
  /// No heap allocation once a pattern of nonzero rows has been seen.
  virtual void solve(const Eigen::VectorXd& f_free, const std::vector<int>* nonzero_rows, Eigen::VectorXd& u) = 0;
  /// solve() under loads.assemble(values), with the loads' nonzero rows.
  void solve(const BodyLoads& loads, const std::vector<Eigen::Vector3d>& values, Eigen::VectorXd& u) {
    loads.assemble(values, load_work_);
    solve(load_work_, &loads.loaded_free_dofs(), u);
  }
  /// Whether u is linear in the loads and prescribed values: then the caller lifts
  /// the prescribed values into the right-hand side (f_free - K_fp u_p). A
  /// nonlinear strategy takes the external force alone and reads the prescribed
  /// values from u (set by the caller before solve()).
  virtual bool linear() const { return true; }
  /// Whether a solve is a back-substitution on a factorisation made once (direct):
  /// then the response to a prescribed group's unit translation is precomputed
  /// (ElasticFrame) instead of lifted into every frame's right-hand side.
  virtual bool factorised() const { return false; }
  /// For a factorised() strategy: U_free = K_ff^-1 F_free for many right-hand sides
  /// at once (#free dofs by k each), faster per column than solve() (a
  /// precomputation of thousands of responses). Others: std::logic_error.
  virtual void solve_columns(const Eigen::MatrixXd& f_free, Eigen::MatrixXd& u_free) {
    (void)f_free, (void)u_free;
    throw std::logic_error("solve_columns: only a factorised elastic solve");
  }
  /// A nonlinear strategy's internal force f_int(u) at the last solution (3 #V),
  /// from which reactions are f - f_int; null for a linear one (then K u).
  virtual const Eigen::VectorXd* internal_force() const { return nullptr; }
  /// Whether this strategy enforces rigid frictionless spheres inside its own solve
  /// (the static Newton solve, the real-time steppers); the linear strategies leave
  /// them to SphereContact (sphere_contact.h), the others take none.
  virtual bool takes_spheres() const { return false; }
  /// Whether this strategy solves the body's springs (ElasticBody::spring_stiffness,
  /// a compliant grasp's pads): a linear one does, as they are in the body's K; a
  /// nonlinear one only if it adds them to the internal force and tangent it
  /// assembles (the Newton solve, VBD, PD). A model refuses a compliant grasp on a
  /// strategy that does not.
  virtual bool takes_springs() const { return linear(); }
  /// Turns the spheres on, acting on `surface_nodes` (the body node of each surface
  /// vertex): from then on spheres() is the set the caller moves before each solve()
  /// and reads the contact from after it. Throws std::logic_error where
  /// takes_spheres() is false.
  void enable_spheres(std::vector<int> surface_nodes) {
    if (!takes_spheres()) throw std::logic_error("this elastic solve does not take spheres");
    spheres_ = std::make_unique<SphereObstacles>(std::move(surface_nodes));
  }
  SphereObstacles* spheres() { return spheres_.get(); }
  /// Solver iterations of the last solve, where meaningful (else 0).
  virtual int last_iterations() const { return 0; }
  /// Facts worth writing beside a result (factor size, preconditioner ...).
  virtual nlohmann::json report() const { return nlohmann::json::object(); }

 protected:
  std::unique_ptr<SphereObstacles> spheres_;  ///< null unless enable_spheres()

 private:
  Eigen::VectorXd load_work_;
};

/// What a strategy may use beyond the body and its parameters.
struct ElasticSolveContext {
  /// A coarser tet mesh of the same body (the two-level preconditioner's coarse
  /// space); null when the model has none.
  const TetMesh* coarse_space = nullptr;
};

/// A strategy: its name, what it is, the parameters it reads (each name prefixed
/// by the model's prefix, "" or "coarse_") and how to make one.
struct ElasticSolveInfo {
  std::string name;
  std::string description;
  /// Its parameters. Two strategies may declare the same name (cg_tolerance) only
  /// with the same spec.
  std::function<std::vector<ParameterSpec>(const std::string& prefix)> parameters;
  /// Throws std::invalid_argument naming the parameter (with its prefix) when the
  /// parameters or the context do not allow it.
  std::function<std::unique_ptr<ElasticSolve>(const ElasticBody&, const Parameters&, const std::string& prefix,
                                              const ElasticSolveContext&)>
      create;
  /// What its instances made from the resolved parameters `p` (names with `prefix`)
  /// answer, known before a body exists so that a model can refuse a tool before
  /// setup (ModelInfo::check_case): "" when a sphere can act on them (linear() ||
  /// takes_spheres()), else why not ("has no contact"); the same for a compliant
  /// grasp's springs (takes_springs()). Checked against instances of every strategy
  /// in tests/models/numerics/elasticity/elastic_solve_tools_test.cc.
  std::function<std::string(const Parameters& p, const std::string& prefix)> refuses_spheres, refuses_springs;
};

/// For ElasticSolveInfo::refuses_spheres and refuses_springs: a strategy that takes
/// the tool with any parameters ("").
inline std::string takes_the_tool(const Parameters&, const std::string&) { return ""; }

/// Every strategy, in one explicit list (elastic_solve.cc).
const std::vector<ElasticSolveInfo>& elastic_solves();

/// The strategies' registry entries (each in its own file).
ElasticSolveInfo direct_solve_info();
ElasticSolveInfo iterative_solve_info();
ElasticSolveInfo corotational_solve_info();
ElasticSolveInfo newton_solve_info();

/// The cg_tolerance parameter (with `prefix`), shared by the strategies that run CG.
std::vector<ParameterSpec> cg_tolerance_parameter(const std::string& prefix);

/// The model parameters that choose and tune an elastic solve, each name prefixed
/// by `prefix` ("" in the fem model: solver, preconditioner, cg_tolerance ...;
/// "coarse_" in the hybrid and embedded models): `solver` and every strategy's own,
/// declared once here for every model that has one.
std::vector<ParameterSpec> elastic_solve_parameters(const std::string& prefix, const std::string& default_solver,
                                                    const std::string& default_preconditioner);

/// The strategy the resolved parameters `p` ask for (names with `prefix`) on `body`
/// (which must outlive it). Throws std::invalid_argument for unusable options.
std::unique_ptr<ElasticSolve> make_elastic_solve(const ElasticBody& body, const Parameters& p,
                                                 const std::string& prefix, const ElasticSolveContext& context = {});

/// The dynamic nonlinear solve: Newton on implicit Euler's equations with the lumped
/// mass, a step of `time_step` seconds per solve() (newton_solve.cc; the fem_dynamic
/// model). Each solve() continues from the state and velocity the last one left.
std::unique_ptr<ElasticSolve> make_implicit_euler_solve(const ElasticBody& body, const std::string& law,
                                                       double tolerance, double time_step);
/// The direct solve alone (CHOLMOD factorisation once): for precomputations.
std::unique_ptr<ElasticSolve> make_direct_solve(const ElasticBody& body);

}  // namespace tb
