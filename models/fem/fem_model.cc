#include "fem_model.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "distributed_elasticity.h"
#include "elastic_solver.h"
#include "surface_load.h"

namespace tb {
namespace {

class FemModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.fine_volume.T.rows() == 0) throw std::invalid_argument("fem: the scenario provides no fine volume mesh");
    mesh_ = &h;
    surface_to_volume_ = h.fine_surface_to_volume;
    surface_u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
    const std::string& solver = p.parameters.choice("solver");
    const int degree = p.parameters.integer("degree");
    const bool neo_hookean = p.parameters.choice("material_law") == "neo_hookean";
    if (solver == "distributed") {
      DistributedSettings s;
      s.degree = degree;
      s.law = neo_hookean ? MaterialLaw::NeoHookean : MaterialLaw::Linear;
      s.cg_tolerance = p.parameters.number("cg_tolerance");
      s.load_steps = p.parameters.integer("load_steps");
      const SupportBox support = p.support;
      distributed_ = std::make_unique<DistributedElasticity>(
          h.fine_volume, p.material, [support](const Eigen::Vector3d& x) { return support.contains(x); }, s,
          MPI_COMM_WORLD);
      return;
    }
    if (degree != 1)
      throw std::invalid_argument("fem: degree " + std::to_string(degree) + " needs solver distributed (the " + solver +
                                  " solver is P1)");
    if (neo_hookean) throw std::invalid_argument("fem: material_law neo_hookean needs solver distributed");
    const SolveMode mode = solver == "direct" ? SolveMode::Direct : SolveMode::Iterative;
    const bool two_level = mode == SolveMode::Iterative && p.parameters.choice("preconditioner") == "two_level";
    if (two_level && h.coarse_volume.T.rows() == 0)
      throw std::invalid_argument(
          "fem: preconditioner two_level needs the scenario's coarse volume mesh; use preconditioner ic");
    solver_ =
        std::make_unique<ElasticSolver>(h.fine_volume, p.material, p.support.select(h.fine_volume.V), mode,
                                        p.parameters.number("cg_tolerance"), two_level ? &h.coarse_volume : nullptr);
    u_ = Eigen::VectorXd::Zero(3 * h.fine_volume.V.rows());
  }

  void step(const PointLoad& load) override {
    if (distributed_) return step_distributed(load);
    require_point_load(load, "fem (solver direct or iterative; a disc load needs solver distributed)");
    if (!have_stencil_ || load.point != stencil_point_) {
      stencil_ = solver_->locate_load(load.point);
      stencil_point_ = load.point;
      have_stencil_ = true;
    }
    solver_->solve(stencil_, load.force, u_);
    // The fine surface's vertices are volume nodes: read their nodal values.
    for (size_t v = 0; v < surface_to_volume_.size(); ++v)
      surface_u_.row(static_cast<Eigen::Index>(v)) = u_.segment<3>(3 * surface_to_volume_[v]).transpose();
  }

  const Displacements& surface_displacement() const override { return surface_u_; }
  int last_iterations() const override {
    return distributed_ ? distributed_->stats().cg_iterations : solver_->last_iterations();
  }

  nlohmann::json statistics() const override {
    nlohmann::json j = nlohmann::json::object();
    if (!distributed_) {
      j["dofs"] = 3 * mesh_->fine_volume.V.rows();
      j["free_dofs"] = solver_->free_dofs();
      j["cells"] = mesh_->fine_volume.T.rows();
      return j;
    }
    const DistributedStats& s = distributed_->stats();
    j["dofs"] = s.dofs;
    j["cells"] = s.cells;
    j["cg_iterations_last_step"] = s.cg_iterations;
    j["cg_condition_estimate"] = s.condition_estimate;
    j["newton_iterations_last_step"] = s.newton_iterations;
    j["load_increments_last_step"] = s.load_increments;
    j["increment_halvings_last_step"] = s.increment_halvings;
    j["load_points"] = load_points_.size();
    j["seconds"] = {{"mesh", s.mesh_s},
                    {"dofs", s.dofs_s},
                    {"assembly", s.assembly_s},
                    {"preconditioner", s.preconditioner_s},
                    {"solve_last_step", s.solve_s}};
    return j;
  }

 private:
  void step_distributed(const PointLoad& load) {
    if (!(load.disc_radius >= 0)) {
      std::ostringstream msg;
      msg << "fem: load.disc_radius " << load.disc_radius << " must be >= 0 (0: point load)";
      throw std::invalid_argument(msg.str());
    }
    // The load's points depend on where and how wide it is, not on its size.
    if (load_points_.empty() || load.point != load_point_ || load.disc_radius != load_radius_) {
      load_points_ = load.disc_radius > 0 ? disc_load_points(mesh_->fine_volume, mesh_->fine_surface,
                                                             surface_to_volume_, load.point, load.disc_radius)
                                          : point_load_points(mesh_->fine_volume, load.point);
      load_point_ = load.point;
      load_radius_ = load.disc_radius;
    }
    distributed_->solve(load_points_, load.force);
    surface_u_ = distributed_->node_displacements(surface_to_volume_);
  }

  const HybridMesh* mesh_ = nullptr;
  std::unique_ptr<ElasticSolver> solver_;
  std::unique_ptr<DistributedElasticity> distributed_;
  std::vector<int> surface_to_volume_;
  Eigen::VectorXd u_;
  Displacements surface_u_;
  LoadStencil stencil_;
  Eigen::Vector3d stencil_point_;
  bool have_stencil_ = false;
  std::vector<LoadPoint> load_points_;  // distributed: the load's points, weights summing to 1
  Eigen::Vector3d load_point_;
  double load_radius_ = 0;
};

}  // namespace

ModelInfo fem_model_info() {
  return {
      "fem",
      "FEM on the fine tet volume (deal.II assembly); the accuracy reference. P1 linear by default; P2 and "
      "neo-Hookean with solver distributed",
      false,
      {{"solver",
        0,
        0,
        0,
        "direct: CHOLMOD factorisation in setup, back-substitution per frame; "
        "iterative: preconditioned CG from the previous frame's solution; "
        "distributed: deal.II over MPI ranks (mpirun), Trilinos CG with AMG, for reference solves",
        {"direct", "iterative", "distributed"},
        "direct"},
       {"preconditioner",
        0,
        0,
        0,
        "of the iterative solver. two_level: incomplete Cholesky plus a coarse correction on the scenario's "
        "coarse (hybrid) tet mesh; ic: incomplete Cholesky alone",
        {"two_level", "ic"},
        "two_level"},
       {"cg_tolerance", 1e-8, 1e-14, 1e-2,
        "relative residual tolerance of the iterative and distributed solvers (each Newton step too)"},
       {"degree", 1, 1, 2, "polynomial degree of the elements, FE_SimplexP (2 needs solver distributed)", {}, {}, true},
       {"material_law",
        0,
        0,
        0,
        "linear: small-strain elasticity (eq. 9); neo_hookean: compressible neo-Hookean with the same lambda, mu, "
        "Newton with load increments (needs solver distributed)",
        {"linear", "neo_hookean"},
        "linear"},
       {"load_steps", 1, 1, 1000, "neo_hookean: load increments per frame (halved when Newton fails)", {}, {}, true}},
      [] { return std::make_unique<FemModel>(); }};
}

}  // namespace tb
