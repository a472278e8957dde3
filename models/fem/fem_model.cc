#include "fem_model.h"

#include <chrono>
#include <stdexcept>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "load_placement.h"

namespace tb {
namespace {

class FemModel : public Model {
 public:
  void setup(const Problem& p) override {
    const HybridMesh& h = *p.mesh;
    if (h.fine_volume.T.rows() == 0) throw std::invalid_argument("fem: the scenario provides no fine volume mesh");
    try {
      body_ = std::make_unique<ElasticBody>(h.fine_volume, p.material,
                                            p.load_case.support.clamp(h.fine_volume.V, "fine volume"));
      // The two-level preconditioner's coarse space is the scenario's coarse (hybrid) mesh.
      solve_ = make_elastic_solve(*body_, p.parameters, "", {h.coarse_volume.T.rows() ? &h.coarse_volume : nullptr});
      // Eq. (10): each load's consistent nodal forces on the fine volume.
      loads_ = std::make_unique<BodyLoads>(
          *body_, place_on_volume(p.load_case.loads, {&h.fine_volume, "fine volume", &h.fine_surface,
                                                      &h.fine_surface_to_volume, p.material.density}));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("fem: ") + e.what());
    }
    surface_to_volume_ = h.fine_surface_to_volume;
    u_ = Eigen::VectorXd::Zero(body_->dofs());
    surface_u_ = Displacements::Zero(h.fine_surface.V.rows(), 3);
  }

  void step(const FrameLoads& loads) override {
    const auto start = std::chrono::steady_clock::now();
    solve_->solve(*loads_, loads.values, u_);
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
  std::unique_ptr<BodyLoads> loads_;
  std::vector<int> surface_to_volume_;
  Eigen::VectorXd u_;
  Displacements surface_u_;
};

}  // namespace

ModelInfo fem_model_info() {
  ModelInfo m;
  m.name = "fem";
  m.description = "Linear FEM on the fine tet volume (P1, deal.II assembly); the accuracy reference";
  m.parameters = elastic_solve_parameters("", "direct", "two_level");
  m.create = [] { return std::make_unique<FemModel>(); };
  m.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction, LoadKind::BodyForce};
  return m;
}

}  // namespace tb
