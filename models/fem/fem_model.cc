#include "fem_model.h"

#include <chrono>
#include <stdexcept>

#include "elastic_solver.h"

namespace tb {
namespace {

class FemModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.fine_volume.T.rows() == 0) throw std::invalid_argument("fem: the scenario provides no fine volume mesh");
    const SolveMode mode = p.parameters.choice("solver") == "direct" ? SolveMode::Direct : SolveMode::Iterative;
    const bool two_level = mode == SolveMode::Iterative && p.parameters.choice("preconditioner") == "two_level";
    if (two_level && h.coarse_volume.T.rows() == 0)
      throw std::invalid_argument(
          "fem: preconditioner two_level needs the scenario's coarse volume mesh; use preconditioner ic");
    solver_ =
        std::make_unique<ElasticSolver>(h.fine_volume, p.material, p.support.select(h.fine_volume.V), mode,
                                        p.parameters.number("cg_tolerance"), two_level ? &h.coarse_volume : nullptr);
    surface_to_volume_ = h.fine_surface_to_volume;
    u_ = Eigen::VectorXd::Zero(3 * h.fine_volume.V.rows());
    surface_u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
  }

  void step(const PointLoad& load) override {
    if (!have_stencil_ || load.point != stencil_point_) {
      stencil_ = solver_->locate_load(load.point);
      stencil_point_ = load.point;
      have_stencil_ = true;
    }
    const auto start = std::chrono::steady_clock::now();
    solver_->solve(stencil_, load.force, u_);
    phases_[0].ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    // The fine surface's vertices are volume nodes: read their nodal values.
    for (size_t v = 0; v < surface_to_volume_.size(); ++v)
      surface_u_.row(static_cast<Eigen::Index>(v)) = u_.segment<3>(3 * surface_to_volume_[v]).transpose();
  }

  const Displacements& surface_displacement() const override { return surface_u_; }
  int last_iterations() const override { return solver_->last_iterations(); }
  const std::vector<PhaseTime>& last_phase_times() const override { return phases_; }

 private:
  std::vector<PhaseTime> phases_{{phase::kSolve}};
  std::unique_ptr<ElasticSolver> solver_;
  std::vector<int> surface_to_volume_;
  Eigen::VectorXd u_;
  Displacements surface_u_;
  LoadStencil stencil_;
  Eigen::Vector3d stencil_point_;
  bool have_stencil_ = false;
};

}  // namespace

ModelInfo fem_model_info() {
  return {"fem",
          "Linear FEM on the fine tet volume (P1, deal.II assembly); the accuracy reference",
          false,
          {{"solver",
            0,
            0,
            0,
            "direct: CHOLMOD factorisation in setup, back-substitution per frame; "
            "iterative: preconditioned CG from the previous frame's solution",
            {"direct", "iterative"},
            "direct"},
           {"preconditioner",
            0,
            0,
            0,
            "of the iterative solver. two_level: incomplete Cholesky plus a coarse correction on the scenario's "
            "coarse (hybrid) tet mesh; ic: incomplete Cholesky alone",
            {"two_level", "ic"},
            "two_level"},
           {"cg_tolerance", 1e-8, 1e-14, 1e-2, "relative residual tolerance of the iterative solver"}},
          [] { return std::make_unique<FemModel>(); }};
}

}  // namespace tb
