#include "fem_model.h"

#include <chrono>
#include <stdexcept>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "load_mapping.h"

namespace tb {
namespace {

class FemModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.fine_volume.T.rows() == 0) throw std::invalid_argument("fem: the scenario provides no fine volume mesh");
    try {
      body_ = std::make_unique<ElasticBody>(h.fine_volume, p.material, p.support.clamp(h.fine_volume.V, "fine volume"));
      // The two-level preconditioner's coarse space is the scenario's coarse (hybrid) mesh.
      solve_ = make_elastic_solve(*body_, p.parameters, "", h.coarse_volume.T.rows() ? &h.coarse_volume : nullptr);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("fem: ") + e.what());
    }
    surface_to_volume_ = h.fine_surface_to_volume;
    u_ = Eigen::VectorXd::Zero(body_->dofs());
    surface_u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
  }

  void step(const PointLoad& load) override {
    require_point_load(load, "fem (a disc load needs the model fem_distributed)");
    const LoadStencil& stencil = stencil_.get(
        load.point, [&](const Eigen::Vector3d& x) { return containing_tet(body_->mesh(), x, "fine volume"); });
    const auto start = std::chrono::steady_clock::now();
    solve_->solve(stencil, load.force, u_);
    phases_[0].ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    // The fine surface's vertices are volume nodes: read their nodal values.
    for (size_t v = 0; v < surface_to_volume_.size(); ++v)
      surface_u_.row(static_cast<Eigen::Index>(v)) = u_.segment<3>(3 * surface_to_volume_[v]).transpose();
  }

  const Displacements& surface_displacement() const override { return surface_u_; }
  int last_iterations() const override { return solve_->last_iterations(); }
  nlohmann::json report() const override { return {{"fine_solve", solve_->report()}}; }
  const std::vector<PhaseTime>& last_phase_times() const override { return phases_; }

 private:
  std::vector<PhaseTime> phases_{{phase::kSolve}};
  std::unique_ptr<ElasticBody> body_;
  std::unique_ptr<ElasticSolve> solve_;
  std::vector<int> surface_to_volume_;
  Eigen::VectorXd u_;
  Displacements surface_u_;
  PerLoadPoint<LoadStencil> stencil_;
};

}  // namespace

ModelInfo fem_model_info() {
  return {"fem", "Linear FEM on the fine tet volume (P1, deal.II assembly); the accuracy reference", false,
          elastic_solve_parameters("", "direct", "two_level"), [] { return std::make_unique<FemModel>(); }};
}

}  // namespace tb
